#!/usr/bin/env bash
# Issue 40: outputs that cannot be mistaken for a finished run. A run into DIR removes an
# earlier run's digest.json and summary.json before it starts and writes its own last,
# each through a temporary file and a rename. So a DIR that holds an earlier run's files
#  1. after a replay that fails while writing its outputs (keyframes.csv blocked by a
#     directory of that name), and
#  2. after a replay killed with SIGKILL mid-run (paced with --rate 1),
# holds neither file; 3. a finished run leaves both and no temporary file.
# Usage: partial_outputs_test.sh ORTHOSONAR WORK_DIR
set -uo pipefail
exe=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }

"$exe" simulate --scene harbor --duration 8 --resolution reduced -o m.mcap -q || fail "simulate"
earlier() { rm -rf "$1" && "$exe" replay m.mcap -o "$1" -q >/dev/null 2>&1 && test -s "$1/digest.json" && test -s "$1/summary.json" ||
  fail "the earlier run into $1"; }

echo "== 1. a run that fails while writing its outputs"
earlier d1
rm -f d1/keyframes.csv && mkdir d1/keyframes.csv
"$exe" replay m.mcap -o d1 -q >fail.out 2>fail.err
rc=$?
[ "$rc" = 2 ] || fail "the blocked run exited $rc (expected 2)"
grep -q "keyframes.csv" fail.err || fail "the error does not name keyframes.csv: $(cat fail.err)"
for f in digest.json summary.json; do
  [ ! -e "d1/$f" ] || fail "a failed run left $f (an earlier run's) in its output directory"
done

echo "== 2. a run killed with SIGKILL mid-run"
earlier d2
"$exe" replay m.mcap -o d2 -q --rate 1 >/dev/null 2>&1 &
pid=$!
sleep 2
kill -0 "$pid" 2>/dev/null || fail "the paced replay ended within 2 s"
kill -KILL "$pid"
wait "$pid" 2>/dev/null
for f in digest.json summary.json; do
  [ ! -e "d2/$f" ] || fail "a killed run left $f (an earlier run's) in its output directory"
done

echo "== 3. a finished run: both files, no temporary"
"$exe" replay m.mcap -o d2 -q >done.out 2>done.err || fail "replay"
test -s d2/digest.json && test -s d2/summary.json || fail "a finished run lacks digest.json or summary.json"
[ -z "$(find d2 -name '*.partial')" ] || fail "temporary files left: $(find d2 -name '*.partial')"
grep -q "$(tail -1 done.out)" d2/digest.json || fail "digest.json is not this run's"
echo PASS
