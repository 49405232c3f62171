#!/usr/bin/env bash
# The central live test (ctest label hal): emulators serve a short simulated mission over the
# real device protocols on loopback, with a device restart (the IMU drops for 0.5 s);
# `orthosonar run` maps it live and records what it consumed; `orthosonar replay` of the
# recording must give the same digest, bit for bit, and the restart must be visible; both
# maps must be non-empty and `orthosonar fuse` of the recording must give the source
# fixture's h/v pairs byte for byte.
# Usage: live_equals_replay.sh <orthosonar executable>
set -euo pipefail
exe="$1"
out="${ORTHOSONAR_TEST_OUT:-$(mktemp -d)}/drivers_live_equals_replay"
rm -rf "$out" && mkdir -p "$out" && cd "$out"
emu_pid=""
cleanup() { if [ -n "$emu_pid" ]; then kill "$emu_pid" 2>/dev/null || true; wait "$emu_pid" 2>/dev/null || true; fi; }
trap cleanup EXIT

"$exe" simulate --scene marina1 --duration 4 --resolution reduced -o sim.mcap -q
"$exe" emulate sim.mcap --rate 2 --status-port 0 --devices-out devices.yaml --linger 3 \
  --outage imu:1.0:0.5 >emulate.out 2>emulate.err &
emu_pid=$!
for _ in $(seq 200); do [ -f devices.yaml ] && break; sleep 0.05; done
[ -f devices.yaml ] || { echo "emulator wrote no devices.yaml"; cat emulate.err; exit 1; }

timeout 60 "$exe" run --devices devices.yaml --record live.mcap -o live --idle-stop 1.0 --metadata-from sim.mcap -q >digest_live.txt
timeout 60 "$exe" replay live.mcap -o replayed -q >digest_replay.txt
a=$(cat digest_live.txt); b=$(cat digest_replay.txt)
echo "live   $a"; echo "replay $b"
[ -n "$a" ] && [ "$a" = "$b" ] || { echo "FAIL: live digest differs from replay digest"; exit 1; }
cmp live/digest.json replayed/digest.json || { echo "FAIL: digest.json files differ"; exit 1; }

# Equal digests of an empty map would prove nothing: both systems must have mapped something.
# And the live run must have consumed the source fixture's sonar data unchanged. Its maps
# cannot equal the source's replay bit for bit (stamps come from the live clock, compressed
# by --rate, navigation crosses the VN-100 wire as float32: docs/DRIVERS.md), but fusing
# every h/v pair in the vehicle frame depends on the images alone: `orthosonar fuse` of the
# recording must give the source fixture's pairs, byte for byte, and the same counts.
/usr/bin/python3 - live <<'PY' || exit 1
import json, sys
for system in ("fusion", "submap"):
    m = json.load(open("%s/%s/metrics.json" % (sys.argv[1], system)))
    print("live %s: coverage %d voxels, %d map points" % (system, m["coverage_voxels"], m["counts"]["map_points"]))
    if m["coverage_voxels"] < 1 or m["counts"]["map_points"] < 1:
        sys.exit("FAIL: the live %s map is empty" % system)
PY
"$exe" fuse sim.mcap -o fuse_source >fuse_source.txt 2>&1 || { echo "FAIL: fuse sim.mcap"; cat fuse_source.txt; exit 1; }
"$exe" fuse live.mcap -o fuse_live >fuse_live.txt 2>&1 || { echo "FAIL: fuse live.mcap"; cat fuse_live.txt; exit 1; }
diff -r fuse_source/pairs fuse_live/pairs >/dev/null || { echo "FAIL: the live run's h/v pairs fuse differently from the source fixture's"; exit 1; }
/usr/bin/python3 - fuse_source/fuse_summary.json fuse_live/fuse_summary.json <<'PY' || exit 1
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
def no_stamps(x):  # the fixture's name and the pairs' stamps are the only allowed differences
    if isinstance(x, dict): return {k: no_stamps(v) for k, v in x.items() if k not in ("stamp_h_ns", "stamp_v_ns", "fixture")}
    if isinstance(x, list): return [no_stamps(v) for v in x]
    return x
print("fuse: source %d pairs, %d fused points; live %d pairs, %d fused points"
      % (a["pairs"], a["matches"], b["pairs"], b["matches"]))
if a["matches"] < 1: sys.exit("FAIL: the source fixture fuses no point; the comparison would be empty")
if no_stamps(a) != no_stamps(b): sys.exit("FAIL: fuse summaries differ beyond stamps and the fixture's name")
PY

# The restart is survived (reconnected, gap closed) and visible in the recording (IMU hole).
node -e '
const r = JSON.parse(require("fs").readFileSync("live/live_faults.json", "utf8"));
const imu = r.devices.find(d => d.name === "imu");
const closed = imu.gaps.filter(g => g.to_ns !== null);
console.log("imu reconnects", imu.reconnects, "closed gaps", closed.length, "consumed", r.events_consumed);
if (imu.reconnects < 1 || closed.length === 0) { console.log("FAIL: the IMU restart was not survived"); process.exit(1); }
for (const d of r.devices) if (d.messages_malformed) { console.log("FAIL: malformed messages from " + d.name); process.exit(1); }
'
"$exe" inspect live.mcap >inspect.txt
# Every gap line of the /imu/data block (under load, small scheduling gaps may come first).
awk '/^  \/imu\/data/{f=1;next} /^  \//{f=0} f && /gap (0\.[1-9]|[1-9])/{found=1} END{exit !found}' inspect.txt || { echo "FAIL: the IMU gap is not visible in the recording"; cat inspect.txt; exit 1; }

# SIGINT ends a live run cleanly: outputs written, recording finalised, replay still equal.
cleanup; emu_pid=""
rm -f devices2.yaml
"$exe" emulate sim.mcap --rate 2 --status-port 0 --devices-out devices2.yaml --linger 5 >emulate2.out 2>emulate2.err &
emu_pid=$!
for _ in $(seq 200); do [ -f devices2.yaml ] && break; sleep 0.05; done
"$exe" run --devices devices2.yaml --record interrupted.mcap -o interrupted -q >digest_int.txt &
run_pid=$!
for _ in $(seq 400); do [ -s interrupted.mcap ] && break; sleep 0.05; done
sleep 1.5
kill -INT "$run_pid"
rc=0; timeout 60 tail --pid="$run_pid" -f /dev/null || { kill -9 "$run_pid"; echo "FAIL: run ignored SIGINT"; exit 1; }
wait "$run_pid" || rc=$?
[ "$rc" = 0 ] || { echo "FAIL: interrupted run exited $rc"; exit 1; }
timeout 60 "$exe" replay interrupted.mcap -o interrupted_replayed -q >digest_int_replay.txt
[ -s digest_int.txt ] && cmp digest_int.txt digest_int_replay.txt || { echo "FAIL: interrupted run does not replay equal"; exit 1; }
"$exe" inspect interrupted.mcap >inspect_int.txt
grep -qi "incomplete\|truncated\|recovered" inspect_int.txt && { echo "FAIL: interrupted recording not finalised"; cat inspect_int.txt; exit 1; }
echo "interrupted run: $(cat digest_int.txt)"
echo "live equals replay: ok"
