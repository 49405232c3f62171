#!/usr/bin/env bash
# ctest drivers:live-equals-replay-gyro: the paper's vehicle with its fibre-optic gyro in the
# loop. A short reduced mission simulated with the `paper` navigation profile (DSP-1760 delta
# angles at 250 Hz) is served by the emulators, the gyro as KVH DSP-1760 packets on its own
# port; `orthosonar run` maps it live (dead reckoning takes its heading from the gyro) and
# records what it consumed; `orthosonar replay` of the recording must give the same digest.
# Every gyro packet must arrive (navigation is never dropped), none malformed, no sequence gap.
# Usage: dsp1760_live_test.sh <orthosonar executable>
set -euo pipefail
exe="$1"
out="${ORTHOSONAR_TEST_OUT:-$(mktemp -d)}/drivers_dsp1760_live"
rm -rf "$out" && mkdir -p "$out" && cd "$out"
emu_pid=""
cleanup() { if [ -n "$emu_pid" ]; then kill "$emu_pid" 2>/dev/null || true; wait "$emu_pid" 2>/dev/null || true; fi; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; exit 1; }

printf 'nav_profile: paper\n' > sim.yaml
"$exe" simulate --scene marina1 --duration 4 --resolution reduced --sim-config sim.yaml -o sim.mcap -q
"$exe" inspect sim.mcap --json > sim_inspect.json
"$exe" emulate sim.mcap --rate 2 --status-port 0 --devices-out devices.yaml --linger 3 >emulate.out 2>emulate.err &
emu_pid=$!
for _ in $(seq 200); do [ -f devices.yaml ] && break; sleep 0.05; done
[ -f devices.yaml ] || { cat emulate.err; fail "emulator wrote no devices.yaml"; }
grep -q 'kind: dsp1760' devices.yaml || { cat devices.yaml; fail "no dsp1760 device in devices.yaml"; }

timeout 60 "$exe" run --devices devices.yaml --record live.mcap -o live --idle-stop 1.0 --metadata-from sim.mcap -q >digest_live.txt
timeout 60 "$exe" replay live.mcap -o replayed -q >digest_replay.txt
a=$(cat digest_live.txt); b=$(cat digest_replay.txt)
echo "live   $a"; echo "replay $b"
[ -n "$a" ] && [ "$a" = "$b" ] || fail "live digest differs from replay digest"
cmp live/digest.json replayed/digest.json || fail "digest.json files differ"
cleanup; emu_pid=""
cat emulate.err

"$exe" inspect live.mcap --json > live_inspect.json
/usr/bin/python3 - sim_inspect.json live_inspect.json live/live_faults.json <<'PY' || exit 1
import json, sys
sim, live, faults = (json.load(open(f)) for f in sys.argv[1:4])
def count(doc, topic):
    text = json.dumps(doc)
    for ch in doc.get("channels", []):
        if ch.get("topic") == topic:
            return ch.get("count", ch.get("messages"))
    sys.exit("FAIL: no channel %s in %s" % (topic, text[:400]))
n_sim, n_live = count(sim, "/gyro"), count(live, "/gyro")
print("gyro events: simulated %d, recorded live %d" % (n_sim, n_live))
if n_sim < 900: sys.exit("FAIL: the paper profile gave %d gyro events in 4 s, want ~1000" % n_sim)
if n_live != n_sim: sys.exit("FAIL: the live run did not record every gyro packet")
gyro = [d for d in faults["devices"] if d["kind"] == "dsp1760"]
if len(gyro) != 1: sys.exit("FAIL: no dsp1760 device in live_faults.json")
g = gyro[0]
print("dsp1760: %d ok, %d malformed, %d sequence gaps" % (g["messages_ok"], g["messages_malformed"], g["sequence_gaps"]))
if g["messages_ok"] != n_sim or g["messages_malformed"] or g["sequence_gaps"]:
    sys.exit("FAIL: gyro packets lost, malformed or out of sequence")
PY
echo "live equals replay with the DSP-1760 in the loop: ok"
