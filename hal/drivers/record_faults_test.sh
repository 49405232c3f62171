#!/usr/bin/env bash
# Issue 40, recording under faults: the emulators serve a short reduced-resolution mission
# (6 s at --rate 2, 3 s of wall time) over the real device protocols on loopback and
# `orthosonar run --record` records it.
#  1. Twenty live runs killed with SIGKILL, 0.1 s to 2.9 s (in steps of 0.147 s) after
#     the recording file appears: from files holding only the scene attachments to ones
#     holding one or two chunks (the recorder closes a chunk about every second of wall
#     time). Every recording opens (inspect exits 1, "recovery: INCOMPLETE"), replays
#     with --allow-incomplete (exit 0, a warning naming the file and the byte offset of
#     the cut), and `recover` makes it whole (its replay exits 0 without
#     --allow-incomplete: the decision inspect prints) with the same digest as the cut
#     recording's. Three of them (kills 3, 10, 17: before, after one and after
#     two chunks) also: replay without --allow-incomplete exits 1 with the same digest,
#     and inspect of the recovered file exits 0 with a summary.
#  2. A live run with --metadata-from a cut fixture warns, names the file and exits 1;
#     the recording it makes is whole.
#  3. That finished live recording cut at 5 offsets, replayed at the CLI: in the magic
#     (exit 2, the file named), in the header record, inside the scene attachment, inside
#     a chunk and in the summary (exit 1, a warning naming the file and the byte offset).
# The sessions of 1 and 2 run four at a time (each mostly waits on the emulator's clock),
# each with its own emulator on ephemeral ports. The sweep of a small fixture cut at every
# 4 KiB boundary, attachments included (no crash, the cut detected with its offset, every
# complete record kept, recovered whole with the same events and digest), runs in-process
# with no process per cut: replay/run/cut_sweep_test.cpp (ctest "orthosonar_run:a small
# fixture cut at every 4 KiB boundary ...").
# Usage: record_faults_test.sh ORTHOSONAR WORK_DIR
set -uo pipefail
exe=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }

"$exe" simulate --scene marina1 --duration 6 --resolution reduced -o sim.mcap -q || fail "simulate"

# In a session's subshell: its emulator (serving sim.mcap at 2x, NAME.yaml), its live run,
# and their end.
emu_pid="" run_pid=""
stop_emulator() { if [ -n "$emu_pid" ]; then kill "$emu_pid" 2>/dev/null; wait "$emu_pid" 2>/dev/null; fi; emu_pid=""; }
stop_session() {
  if [ -n "$run_pid" ]; then kill -KILL "$run_pid" 2>/dev/null; wait "$run_pid" 2>/dev/null; fi
  run_pid=""
  stop_emulator
}
start_emulator() {
  rm -f "$1.yaml"
  "$exe" emulate sim.mcap --rate 2 --status-port 0 --devices-out "$1.yaml" --linger 2 >"$1.emu.out" 2>"$1.emu.err" &
  emu_pid=$!
  for _ in $(seq 200); do [ -f "$1.yaml" ] && break; sleep 0.05; done
  [ -f "$1.yaml" ] || { cat "$1.emu.err"; fail "the emulator wrote no $1.yaml"; }
}

# check_cut FILE [full]: a cut recording opens, replays with --allow-incomplete, and
# recover makes it whole with the same digest. "full" adds the replay without
# --allow-incomplete (exit 1) and inspect of the recovered file (exit 0, a summary).
check_cut() {
  local f=$1 base=${1%.mcap} rc
  timeout 20 "$exe" inspect "$f" >"$base.inspect" 2>&1
  rc=$?
  [ "$rc" = 1 ] || { cat "$base.inspect"; fail "$f: inspect exited $rc (expected 1, a cut file)"; }
  grep -q "recovery: INCOMPLETE" "$base.inspect" || fail "$f: inspect does not say INCOMPLETE"
  timeout 20 "$exe" replay "$f" -o "$base.r" -q --allow-incomplete >"$base.digest" 2>"$base.replay.err"
  rc=$?
  [ "$rc" = 0 ] || { tail -3 "$base.replay.err"; fail "$f: replay --allow-incomplete exited $rc"; }
  grep -q "^warning: $f: input cut at byte offset [0-9]* of $(stat -c %s "$f") bytes" "$base.replay.err" ||
    { tail -3 "$base.replay.err"; fail "$f: replay --allow-incomplete does not warn of the cut"; }
  if [ "${2:-}" = full ]; then
    timeout 20 "$exe" replay "$f" -o "$base.r" -q >"$base.strict.digest" 2>"$base.strict.err"
    rc=$?
    [ "$rc" = 1 ] || { tail -3 "$base.strict.err"; fail "$f: replay exited $rc (expected 1)"; }
    grep -q "exit 1: 1 input was cut short" "$base.strict.err" || fail "$f: replay does not say why it exits 1"
    cmp -s "$base.digest" "$base.strict.digest" || fail "$f: replay digest differs with --allow-incomplete"
  fi
  timeout 20 "$exe" recover "$f" -o "$base.whole.mcap" -q >/dev/null 2>"$base.recover.err" ||
    { cat "$base.recover.err"; fail "$f: recover exited $?"; }
  timeout 20 "$exe" replay "$base.whole.mcap" -o "$base.w" -q >"$base.whole.digest" 2>"$base.whole.err"
  rc=$?
  [ "$rc" = 0 ] || { tail -3 "$base.whole.err"; fail "$base.whole.mcap: replay exited $rc (expected 0, whole)"; }
  ! grep -q "input cut" "$base.whole.err" || fail "$base.whole.mcap: replay says it is cut"
  cmp -s "$base.digest" "$base.whole.digest" ||
    fail "$f: recovered digest $(cat "$base.whole.digest") != --allow-incomplete digest $(cat "$base.digest")"
  if [ "${2:-}" = full ]; then
    timeout 20 "$exe" inspect "$base.whole.mcap" >"$base.whole.inspect" 2>&1 ||
      { tail -3 "$base.whole.inspect"; fail "$base.whole.mcap: inspect exited $? (expected 0, whole)"; }
    grep -q "^summary: present" "$base.whole.inspect" || fail "$base.whole.mcap: no summary"
  fi
}

# kill_session I DELAY: a live run killed DELAY s after its recording file appears.
kill_session() {
  local i=$1 delay=$2 f=killed$1.mcap
  start_emulator "emu$i"
  "$exe" run --devices "emu$i.yaml" --record "$f" -o "live$i" --metadata-from sim.mcap -q >/dev/null 2>"run$i.err" &
  run_pid=$!
  for _ in $(seq 500); do [ -s "$f" ] && break; sleep 0.02; done
  [ -s "$f" ] || { cat "run$i.err"; fail "the live run wrote no $f"; }
  sleep "$delay"
  kill -0 "$run_pid" 2>/dev/null || { cat "run$i.err"; fail "the live run ended before the kill at $delay s"; }
  stop_session  # SIGKILL
  check_cut "$f" $([ $((i % 7)) = 3 ] && echo full)
  echo "kill $i at $delay s: $(grep -o 'recovered [0-9]* of [0-9]* bytes, [0-9]* messages' "killed$i.inspect")"
}

# metadata_session: a whole live run with --metadata-from a cut fixture (section 2).
metadata_session() {
  head -c $(($(stat -c %s sim.mcap) * 7 / 10)) sim.mcap >simcut.mcap
  start_emulator emu_meta
  timeout 60 "$exe" run --devices emu_meta.yaml --record full.mcap -o live_full --idle-stop 1.0 \
    --metadata-from simcut.mcap -q >/dev/null 2>run_meta.err
  local rc=$?
  stop_emulator
  [ "$rc" = 1 ] || { tail -3 run_meta.err; fail "run --metadata-from a cut fixture exited $rc (expected 1)"; }
  grep -q "warning: simcut.mcap: input cut at byte offset [0-9]* of [0-9]* bytes; recovered [0-9.]* s of sensor time" run_meta.err ||
    { cat run_meta.err; fail "run --metadata-from: no warning naming the cut fixture"; }
  "$exe" inspect full.mcap >/dev/null 2>&1 || fail "the finished live recording is not whole"
  echo "run --metadata-from simcut.mcap: exit 1 with the warning; full.mcap whole"
}

# Sessions run in background subshells, at most four at a time; each leaves NAME.ok when
# it passed and NAME.log either way.
# On exit (a failure in this shell, or ctest's timeout), the sessions still running.
stop_sessions() { for p in $(jobs -rp); do kill "$p" 2>/dev/null; done; wait 2>/dev/null; }
trap stop_sessions EXIT
trap 'exit 1' TERM INT
spawn() {
  local name=$1
  shift
  while [ "$(jobs -rp | wc -l)" -ge 4 ]; do wait -n; done
  ( trap stop_session EXIT; trap 'exit 1' TERM; "$@" && touch "$name.ok" ) >"$name.log" 2>&1 &
}

echo "== 1. twenty live runs killed with SIGKILL; 2. run --metadata-from a cut fixture"
spawn meta metadata_session
names=(meta)
for i in $(seq 0 19); do
  spawn "kill$i" kill_session "$i" "$(awk -v i="$i" 'BEGIN { printf "%.3f", 0.1 + 0.147 * i }')"
  names+=("kill$i")
done
wait
bad=0
for n in "${names[@]}"; do
  cat "$n.log"
  [ -f "$n.ok" ] || { echo "FAIL: session $n (above)" >&2; bad=1; }
done
[ "$bad" = 0 ] || exit 1
with_messages=$(grep -h -o 'bytes, [1-9][0-9]* messages' kill*.log | wc -l)
# The kills span the mission: the first before any chunk (the scene attachments only), at
# least a quarter after one or more chunks.
[ "$with_messages" -ge 5 ] && [ "$with_messages" -lt 20 ] ||
  fail "$with_messages of 20 killed recordings hold messages (expected 5..19: the kills should span the mission)"

echo "== 3. the finished live recording cut at 5 offsets"
size=$(stat -c %s full.mcap)
# cut_replay OFF EXPECT: replay of full.mcap's first OFF bytes exits EXPECT, naming the file.
cut_replay() {
  local off=$1 expect=$2 f=at$1.mcap rc
  head -c "$off" full.mcap >"$f"
  timeout 20 "$exe" replay "$f" -o "at$off.r" -q >"at$off.out" 2>"at$off.err"
  rc=$?
  [ "$rc" = "$expect" ] || { tail -3 "at$off.err"; fail "replay of full.mcap cut at byte $off exited $rc, expected $expect (124: hung; >128: crashed)"; }
  if [ "$expect" = 1 ]; then
    grep -q "^warning: $f: input cut at byte offset [0-9]* of $off bytes" "at$off.err" ||
      { tail -3 "at$off.err"; fail "replay of full.mcap cut at byte $off: no warning naming $f and the offset"; }
    grep -q "exit 1: 1 input was cut short" "at$off.err" || fail "replay of $f: no reason for exit 1"
  else
    grep -q "$f" "at$off.err" || { tail -3 "at$off.err"; fail "replay of full.mcap cut at byte $off: no message naming $f"; }
  fi
  echo "cut at $off: exit $rc"
}
cut_replay 5 2                        # in the magic
cut_replay 20 1                       # in the header record
cut_replay 400000 1                   # inside the scene mesh attachment
cut_replay $((size * 6 / 10 + 37)) 1  # inside a chunk
cut_replay $((size - 200)) 1          # in the summary
echo PASS
