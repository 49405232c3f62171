#!/usr/bin/env bash
# `orthosonar batch` on this machine (docs/BATCH.md), as a user runs it:
#  1. a sweep plan (2 scenes x 3 cells, 2 cells per task: 4 shards) run by
#     `batch local` merges into the same bytes as the one-machine `orthosonar sweep`
#     (tables, grids, seed summary, the reference cell's maps and digest);
#  2. a second run skips every task (results keyed by input digests);
#  3. an injected failure (the task's fixture path is a folder) is retried, reported by
#     name with its log, and the merge names the missing task and exits 2; once fixed, a
#     re-run redoes only that task and the merge is identical again;
#  4. the task index comes from $SLURM_ARRAY_TASK_ID or $JOB_COMPLETION_INDEX;
#  5. verify and golden plans merge into a summary and JUnit XML (one case per fixture or
#     scenario; a differing digest is a <failure> naming the outputs, a missing result an
#     <error>), with exit codes 0 / 1 / 2 (the golden scenario is a copy whose expectations
#     this build writes first, so the step holds under every compiler).
# Usage: batch_local_test.sh ORTHOSONAR SOURCE_DIR WORK_DIR
set -euo pipefail
exe=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }

common=(--scenes aircraft,harbor --seeds 1 --cells 1/30,3/30,5/90 --duration 20 --resolution reduced --no-report)

# Outputs that must be the same bytes: everything but timings (runtime.*, summary.json and
# the runtime blocks of metrics.json, covered by digest.json), the report and fixtures.
same_bytes() {
  diff -r -x '*.mcap' -x 'runtime.*' -x summary.json -x metrics.json -x report "$1" "$2" >/dev/null ||
    { diff -r -x '*.mcap' -x 'runtime.*' -x summary.json -x metrics.json -x report "$1" "$2" | head -20; fail "$3"; }
}

echo "== 1. sweep: batch local vs one machine"
"$exe" batch plan sweep "${common[@]}" --cells-per-task 2 -o plan >plan.txt
grep -q "^plan: sweep, 4 tasks" plan.txt || fail "expected 4 tasks: $(cat plan.txt)"
"$exe" batch local plan -j 2 >local.txt 2>local.err || fail "batch local exited $?: $(tail -5 local.err)"
"$exe" sweep "${common[@]}" -o single >single.txt 2>single.err || fail "sweep exited $?"
for f in seeds.md seeds.json aircraft/seed1/grid.json harbor/seed1/tables.md; do
  test -s "plan/merged/$f" || fail "merged output $f missing"
done
same_bytes single plan/merged "batch merge differs from the one-machine sweep"
cmp -s single.txt local.txt || fail "printed tables differ"
echo "identical: $(find plan/merged -type f -not -path '*/report/*' | wc -l) files"

echo "== 1b. one scene and seed with the reference cell's maps and the report"
"$exe" batch plan sweep --scenes aircraft --seeds 2 --cells 3/30,5/90 --duration 20 --resolution reduced -o rplan >/dev/null
"$exe" batch local rplan -j 2 >/dev/null 2>rlocal.err || fail "batch local (report) exited $?: $(tail -5 rlocal.err)"
"$exe" sweep --scene aircraft --seed 2 --cells 3/30,5/90 --duration 20 --resolution reduced -o rsingle >/dev/null 2>&1
for f in grid.json digest.json submap/map.ply report/report.html; do
  test -s "rplan/merged/$f" || fail "merged output $f missing"
done
same_bytes rsingle rplan/merged "batch merge (with the reference cell) differs from the one-machine sweep"

echo "== 2. resume: every task skipped"
"$exe" batch local plan -j 2 >/dev/null 2>resume.err || fail "second batch local exited $?"
n=$(grep -c "result is current" plan/logs/task-*.log | awk -F: '{s+=$2} END {print s}')
[ "$n" -ge 4 ] || fail "expected 4 skipped tasks, logs say $n"

echo "== 3. injected failure: retried, reported, merge exits 2; fixed: only that task reruns"
rm -rf plan/results/3 plan/fixtures/harbor-seed1.mcap && mkdir plan/fixtures/harbor-seed1.mcap
set +e
"$exe" batch local plan -j 2 --retries 1 >inj.txt 2>inj.err
rc=$?
set -e
[ "$rc" -eq 2 ] || fail "batch local with a failing task exited $rc, expected 2"
grep -q "task 3 (harbor/seed1/5m90-5m90) attempt 1 failed" inj.err || fail "no retry reported: $(cat inj.err)"
grep -q "task 3 (harbor/seed1/5m90-5m90) FAILED after 2 attempt(s): .*Is a directory.*log .*logs/task-3.log" inj.err ||
  fail "failure not reported by name with its log: $(cat inj.err)"
grep -q "1 of 4 task results missing" inj.err || fail "merge did not count the missing task"
set +e; "$exe" batch status plan >status.txt; src_rc=$?; set -e
[ "$src_rc" -eq 1 ] && grep -q "^3 harbor/seed1/5m90-5m90 failed" status.txt || fail "status: $(cat status.txt)"
rmdir plan/fixtures/harbor-seed1.mcap
"$exe" batch local plan -j 2 >fixed.txt 2>fixed.err || fail "re-run after the fix exited $?"
grep -q "task 3 (harbor/seed1/5m90-5m90): attempt 1 on" plan/logs/task-3.log || fail "task 3 did not rerun"
n=$(grep -c "result is current" plan/logs/task-2.log)
[ "$n" -ge 3 ] || fail "task 2 was not skipped on the re-runs ($n skips)"
same_bytes single plan/merged "merge after the resumed run differs"

echo "== 4. task index from the environment"
SLURM_ARRAY_TASK_ID=0 "$exe" batch run plan 2>env1.err && grep -q "task 0 (aircraft/seed1/1m30-3m30)" env1.err ||
  fail "SLURM_ARRAY_TASK_ID not used: $(cat env1.err)"
JOB_COMPLETION_INDEX=3 "$exe" batch run plan 2>env2.err && grep -q "task 3 (harbor/seed1/5m90-5m90)" env2.err ||
  fail "JOB_COMPLETION_INDEX not used: $(cat env2.err)"
set +e; JOB_COMPLETION_INDEX=4 "$exe" batch run plan 2>env3.err; rc=$?; set -e
[ "$rc" -eq 2 ] && grep -q "JOB_COMPLETION_INDEX = 4: the plan has tasks 0..4-1" env3.err || fail "bad index accepted: $(cat env3.err)"

echo "== 5. verify and golden: summary and JUnit XML"
mkdir -p vf
cp rsingle/aircraft.mcap vf/a1.mcap
cp single/harbor/seed1/harbor.mcap vf/h2.mcap
cp rsingle/digest.json vf/a1.digest.json      # its own digest (reference cell, default systems): matches
cp rsingle/digest.json vf/h2.digest.json      # another mission's digest: differs
"$exe" batch plan verify vf -o vplan >/dev/null
set +e; "$exe" batch local vplan -j 2 >v.txt 2>v.err; rc=$?; set -e
[ "$rc" -eq 1 ] || fail "verify merge with a differing digest exited $rc, expected 1"
grep -q "| a1 | identical" v.txt && grep -q "| h2 | DIFFERENT" v.txt || fail "verify summary: $(cat v.txt)"
grep -q '<failure message="expected .*type="digest">' vplan/merged/junit.xml || fail "no JUnit failure for h2"
grep -q "submap/map: expected" vplan/merged/junit.xml || fail "JUnit failure does not name the differing outputs"
rm vf/a1.mcap && rm -rf vplan/results/0                     # a fixture lost after planning
set +e; "$exe" batch local vplan -j 2 --retries 0 >v2.txt 2>v2.err; rc=$?; set -e
[ "$rc" -eq 2 ] || fail "verify with a missing fixture exited $rc, expected 2"
grep -q '<error message="no result: failed: .*a1.mcap' vplan/merged/junit.xml || fail "no JUnit error for the lost fixture"
# The golden plan runs a copy of the aircraft scenario whose expectations this build writes
# first (`golden --update`): digests are defined for the reference build only (README,
# "Presets"), and this step checks the batch plumbing, not the digests, in every build.
mkdir -p gs/scenarios
cp "$src/golden/bounds.yaml" gs/bounds.yaml
cp "$src/golden/scenarios/aircraft.yaml" gs/scenarios/aircraft.yaml
"$exe" golden --update gs/scenarios/aircraft.yaml --no-images -o gupdate >gupdate.txt 2>&1 \
  || fail "golden --update of the copied scenario exited $?: $(tail -5 gupdate.txt)"
"$exe" batch plan golden gs/scenarios/aircraft.yaml --no-images -o gplan >/dev/null
"$exe" batch local gplan -j 1 >g.txt 2>g.err || fail "golden batch exited $?: $(tail -5 g.err)"
grep -q "| aircraft | PASS |" g.txt || fail "golden summary: $(cat g.txt)"
for x in vplan/merged/junit.xml gplan/merged/junit.xml; do
  /usr/bin/python3 - "$x" <<'EOF' || fail "$x is not well-formed JUnit XML"
import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == "testsuites", root.tag
cases = root.findall("./testsuite/testcase")
assert len(cases) == int(root.get("tests")) > 0
EOF
done

echo "== 6. bad input: clear errors, exit 2"
set +e
"$exe" batch plan sweep --scenes atlantis --seeds 1 -o bad 2>bad1.err; r1=$?
"$exe" batch plan sweep --scenes harbor --seeds 1 --cells 6/30 -o bad 2>bad2.err; r2=$?
"$exe" batch run nowhere --task 0 2>bad3.err; r3=$?
set -e
[ $r1 -eq 2 ] && grep -q "atlantis" bad1.err || fail "unknown scene: rc $r1 $(cat bad1.err)"
[ $r2 -eq 2 ] && grep -q "'6/30' is not a cell" bad2.err || fail "bad cell: rc $r2 $(cat bad2.err)"
[ $r3 -eq 2 ] && grep -q "not a batch plan" bad3.err || fail "no plan: rc $r3 $(cat bad3.err)"
echo "batch local: all checks passed"
