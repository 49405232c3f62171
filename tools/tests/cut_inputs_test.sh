#!/usr/bin/env bash
# Issue 40: every command that reads a fixture says when it was cut short. A cut input
# gives a warning naming the file, the byte offset and what was recovered (seconds of
# sensor time, messages), is recorded in summary.json (and the report), and the command
# exits 1 (README, "Exit codes"); --allow-incomplete exits 0 and still records it. A whole
# fixture exits 0 and records "complete": true. Batch merge names the tasks whose inputs
# were cut. Commands: replay, verify, sweep, fuse, report, perception-check --fixture,
# export, import of a cut bag, batch (verify tasks). `run --metadata-from` is covered by
# record_faults_test.sh (it needs the emulator).
# Usage: cut_inputs_test.sh ORTHOSONAR WORK_DIR
set -uo pipefail
exe=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }

# expect CODE NAME CMD...: runs CMD (stderr to NAME.err), checks its exit code.
expect() {
  local want=$1 name=$2
  shift 2
  "$@" >"$name.out" 2>"$name.err"
  local rc=$?
  [ "$rc" = "$want" ] || { tail -5 "$name.err" >&2; fail "$name: exit $rc, expected $want: $*"; }
}
# warned NAME FILE: NAME.err names FILE, the byte offset and what was recovered.
warned() {
  grep -q "warning: .*$2.*input cut at byte offset [0-9]* of [0-9]* bytes; recovered [0-9.]* s of sensor time, [0-9]* messages" "$1.err" ||
    { cat "$1.err" >&2; fail "$1: no warning naming $2, the byte offset and what was recovered"; }
}
json_get() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$1" "$2"; }

"$exe" simulate --scene harbor --duration 8 --resolution reduced --labels -o whole.mcap -q || fail "simulate"
size=$(stat -c %s whole.mcap)
head -c $((size * 8 / 10)) whole.mcap >tail20.mcap   # the last 20 % gone
head -c 700000 whole.mcap >inattach.mcap             # inside the embedded scene mesh (the 2nd attachment)

echo "== replay"
expect 0 replay-whole "$exe" replay whole.mcap -o r-whole -q
[ "$(json_get r-whole/summary.json "d['input']['complete']")" = True ] || fail "whole: summary.json input.complete"
! grep -q "input cut" replay-whole.err || fail "whole fixture warned"
expect 1 replay-cut "$exe" replay tail20.mcap -o r-cut -q
warned replay-cut tail20.mcap
[ "$(json_get r-cut/summary.json "d['input']['complete']")" = False ] || fail "cut: summary.json input.complete"
[ "$(json_get r-cut/summary.json "d['input']['cut_at_byte'] > 0 and d['input']['messages_recovered'] > 0 and d['input']['sensor_s_recovered'] > 0")" = True ] ||
  fail "cut: summary.json input fields: $(json_get r-cut/summary.json "d['input']")"
expect 0 replay-allow "$exe" replay tail20.mcap -o r-allow -q --allow-incomplete
warned replay-allow tail20.mcap
[ "$(json_get r-allow/summary.json "d['input']['complete']")" = False ] || fail "--allow-incomplete: not recorded"
cmp -s replay-cut.out replay-allow.out || fail "--allow-incomplete changed the digest"
"$exe" replay inattach.mcap -o r-attach -q >replay-attach.out 2>replay-attach.err
rc=$?
[ "$rc" = 1 ] || [ "$rc" = 2 ] || fail "cut inside an attachment: exit $rc (expected 1 or 2)"
grep -q "inattach.mcap" replay-attach.err || fail "cut inside an attachment: no message naming the file"

echo "== verify"
cp r-allow/digest.json cut.digest.json
expect 1 verify-cut "$exe" verify tail20.mcap --expect cut.digest.json
warned verify-cut tail20.mcap
grep -q "^identical" verify-cut.out || fail "verify: the digest itself should match"
expect 0 verify-allow "$exe" verify tail20.mcap --expect cut.digest.json --allow-incomplete
expect 0 verify-whole "$exe" verify whole.mcap --expect r-whole/digest.json

echo "== fuse"
expect 1 fuse-cut "$exe" fuse tail20.mcap -o fuse-cut
warned fuse-cut tail20.mcap
[ "$(json_get fuse-cut/fuse_summary.json "d['input_complete']")" = False ] || fail "fuse: not recorded"
expect 0 fuse-allow "$exe" fuse tail20.mcap -o fuse-allow --allow-incomplete

echo "== sweep --fixture"
expect 1 sweep-cut "$exe" sweep --fixture tail20.mcap --cells 3/30 --workers 1 -o sweep-cut
warned sweep-cut tail20.mcap
[ "$(json_get sweep-cut/summary.json "d['input']['complete']")" = False ] || fail "sweep: summary.json input"
expect 0 sweep-allow "$exe" sweep --fixture tail20.mcap --cells 3/30 --workers 1 --no-report -o sweep-allow --allow-incomplete
# Without the report (no summary.json), grid.json and tables.md still record the cut.
grep -q '"input_cut": "tail20.mcap: input cut at byte offset' sweep-allow/grid.json || fail "sweep --no-report: grid.json does not record the cut"
grep -q "INPUT CUT SHORT:\*\* tail20.mcap: input cut at byte offset" sweep-allow/tables.md || fail "sweep --no-report: tables.md does not record the cut"

echo "== report"
expect 1 report-cut "$exe" report r-cut -o rep-cut --allow-no-display
grep -q "r-cut: input tail20.mcap was cut at byte offset [0-9]* of [0-9]* bytes" report-cut.err || fail "report: no warning"
grep -q "INCOMPLETE INPUT: input tail20.mcap was cut" rep-cut/report.html || fail "report.html does not say the input was cut"
expect 0 report-allow "$exe" report r-cut -o rep-allow --allow-no-display --allow-incomplete
expect 0 report-whole "$exe" report r-whole -o rep-whole --allow-no-display
! grep -q "INCOMPLETE INPUT" rep-whole/report.html || fail "report of a whole run says INCOMPLETE"

echo "== perception-check --fixture"
expect 1 pc-cut "$exe" perception-check --fixture tail20.mcap --every 10
warned pc-cut tail20.mcap
expect 0 pc-allow "$exe" perception-check --fixture tail20.mcap --every 10 --allow-incomplete

echo "== export, and import of a cut bag"
expect 1 export-cut "$exe" export tail20.mcap --to ros1-bag -o cut-export.bag -q
warned export-cut tail20.mcap
expect 0 export-whole "$exe" export whole.mcap --to ros1-bag -o whole.bag -q
bsize=$(stat -c %s whole.bag)
head -c $((bsize * 7 / 10)) whole.bag >cut.bag
expect 1 import-cut "$exe" import cut.bag --map whole.topics.yaml -o imported.mcap -q
grep -q "warning: cut.bag: input cut, kept [0-9]* of [0-9]* bytes.*recovered [0-9.]* s of sensor time, [0-9]* messages" import-cut.err ||
  { cat import-cut.err >&2; fail "import: no warning naming the bag, the offset and what was recovered"; }
expect 0 import-allow "$exe" import cut.bag --map whole.topics.yaml -o imported2.mcap -q --allow-incomplete
expect 0 import-whole "$exe" import whole.bag --map whole.topics.yaml -o imported3.mcap -q

echo "== batch: merge names the task whose input was cut"
mkdir -p suite && cp whole.mcap suite/whole.mcap && cp r-whole/digest.json suite/whole.digest.json
cp tail20.mcap suite/tail20.mcap && cp cut.digest.json suite/tail20.digest.json
expect 0 plan "$exe" batch plan verify suite -o plan
expect 1 batch-cut "$exe" batch local plan -j 1
grep -q "batch task [0-9]* (.*tail20.*): .*tail20.mcap: input cut at byte offset" batch-cut.err || { cat batch-cut.err >&2; fail "merge does not name the cut task"; }
grep -q "whole.*: .*input cut" batch-cut.err && fail "merge names the whole task as cut"
[ "$(json_get plan/merged/summary.json "[t['name'] for t in d['input_cut_tasks']]" | grep -c tail20)" = 1 ] ||
  fail "summary.json input_cut_tasks: $(json_get plan/merged/summary.json "d['input_cut_tasks']")"
expect 0 merge-allow "$exe" batch merge plan --allow-incomplete

echo "PASS"
