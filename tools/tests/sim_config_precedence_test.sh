#!/bin/sh
# One simulator config file, one mission (issue 35): `simulate --sim-config`, `sweep --sim-config`
# and `batch plan sweep --sim-config` take duration_s, seed and resolution from the file
# unless the flag is actually given; a flag given wins. (simulate used to overwrite the
# file's values with its flags' defaults.) Usage: sim_config_precedence_test.sh ORTHOSONAR OUT_DIR
set -e
cli=$1; out=$2
rm -rf "$out"; mkdir -p "$out"
printf 'duration_s: 1\nseed: 7\nresolution: reduced\nrender_threads: 1\n' > "$out/sim.yaml"
expect() {  # expect FILE 'fragment' 'what'
  grep -q -- "$2" "$1" || { echo "FAIL: $3: no '$2' in:"; cat "$1"; exit 1; }
  echo "ok: $3"
}

# simulate: the file's values, then flags given over them.
"$cli" simulate --scene aircraft --sim-config "$out/sim.yaml" > "$out/simulate_file.txt"
expect "$out/simulate_file.txt" ': 1.0 s, seed 7, reduced,' "simulate takes duration_s, seed, resolution from --sim-config"
# --config, the option's old name, still reads the file, and says so on stderr.
"$cli" simulate --scene aircraft --config "$out/sim.yaml" > "$out/simulate_old.txt" 2> "$out/simulate_old.err"
expect "$out/simulate_old.txt" ': 1.0 s, seed 7, reduced,' "simulate --config (the old name) still reads the file"
expect "$out/simulate_old.err" 'now --sim-config' "simulate --config says it is now --sim-config"
if "$cli" simulate --scene aircraft --config "$out/sim.yaml" --sim-config "$out/sim.yaml" --duration 0.2 > /dev/null 2> "$out/both.err"; then
  echo "FAIL: --config and --sim-config together accepted"; exit 1
fi
expect "$out/both.err" 'give one of them' "simulate --config with --sim-config is an error"
"$cli" simulate --scene aircraft --sim-config "$out/sim.yaml" --duration 0.5 --seed 3 > "$out/simulate_flags.txt"
expect "$out/simulate_flags.txt" ': 0.5 s, seed 3, reduced,' "simulate --duration/--seed given override --sim-config"
"$cli" simulate --scene aircraft --sim-config "$out/sim.yaml" --duration 0.2 --resolution full > "$out/simulate_res.txt"
expect "$out/simulate_res.txt" ': 0.2 s, seed 7, full,' "simulate --resolution given overrides --sim-config"
# A --profile that contradicts the file's profile is an error, not a silent choice.
printf 'profile: clean\n' > "$out/clean.yaml"
if "$cli" simulate --scene aircraft --sim-config "$out/clean.yaml" --profile field --duration 0.2 > /dev/null 2> "$out/profile.err"; then
  echo "FAIL: --profile field with 'profile: clean' accepted"; exit 1
fi
expect "$out/profile.err" "contradicts" "simulate --profile contradicting the file is an error"

# batch plan sweep: the plan records the resolved mission.
"$cli" batch plan sweep --scenes aircraft --sim-config "$out/sim.yaml" -o "$out/plan_file" > /dev/null
python3 - "$out/plan_file/manifest.json" 1 reduced 7 <<'EOF'
import json, sys
m = json.load(open(sys.argv[1]))
c = m["common"]
seeds = sorted({t["spec"]["seed"] for t in m["tasks"]})
got = (c["duration_s"], c["resolution"], seeds)
want = (float(sys.argv[2]), sys.argv[3], [int(s) for s in sys.argv[4].split(",")])
if got != want:
    sys.exit(f"FAIL: batch plan {sys.argv[1]}: duration, resolution, seeds {got}, expected {want}")
EOF
echo "ok: batch plan sweep takes duration_s, seed, resolution from --sim-config"
"$cli" batch plan sweep --scenes aircraft --sim-config "$out/sim.yaml" --duration 4 --seeds 2,3 --resolution full \
  -o "$out/plan_flags" > /dev/null
python3 - "$out/plan_flags/manifest.json" 4 full 2,3 <<'EOF'
import json, sys
m = json.load(open(sys.argv[1]))
c = m["common"]
seeds = sorted({t["spec"]["seed"] for t in m["tasks"]})
got = (c["duration_s"], c["resolution"], seeds)
want = (float(sys.argv[2]), sys.argv[3], [int(s) for s in sys.argv[4].split(",")])
if got != want:
    sys.exit(f"FAIL: batch plan {sys.argv[1]}: duration, resolution, seeds {got}, expected {want}")
EOF
echo "ok: batch plan sweep flags given override --sim-config"

# sweep: the simulated fixture is the file's mission (its metadata records it).
"$cli" sweep --scene aircraft --sim-config "$out/sim.yaml" --cells 3/30 --no-report -o "$out/sweep" > /dev/null 2>&1
"$cli" inspect "$out/sweep/aircraft.mcap" > "$out/sweep_inspect.txt"
expect "$out/sweep_inspect.txt" '  seed: 7$' "sweep takes seed from --sim-config"
expect "$out/sweep_inspect.txt" '  resolution: reduced$' "sweep takes resolution from --sim-config"
expect "$out/sweep_inspect.txt" '  duration_s: 1$' "sweep takes duration_s from --sim-config"
