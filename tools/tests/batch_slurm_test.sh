#!/usr/bin/env bash
# `orthosonar batch slurm` on a real one-node Slurm cluster started by this test on loopback
# (tools/tests/slurm_cluster.sh: munged, slurmctld, slurmd; own key, ports, state, spool and
# logs), as docs/BATCH.md describes:
#  1. a sweep plan (2 scenes x 2 seeds x 3 cells, reduced resolution) with one task made to
#     fail (its fixture path is a folder) is submitted with --submit --wait: the task is
#     retried, reported with its log path, the dependent merge job names it and fails, and
#     --wait exits non-zero;
#  2. after the fix a re-submission reruns only that task (the others' results are current)
#     and the merge job succeeds;
#  3. the merged outputs equal `batch local` and the one-machine `orthosonar sweep`, byte for
#     byte (timings aside);
#  4. every daemon started is stopped by PID on exit, failure included, and checked gone.
# Usage: batch_slurm_test.sh ORTHOSONAR SOURCE_DIR WORK_DIR
# Skips (77) without root or the Slurm packages, except under CI=true, where that fails.
set -euo pipefail
exe=$1 src=$2 work=$3
skip() {
  if [ "${CI:-}" = true ]; then echo "FAIL (CI must run this test): $*" >&2; exit 1; fi
  echo "SKIP: $*"; exit 77
}
[ "$(id -u)" -eq 0 ] || skip "needs root (SlurmUser=root, munged as root)"
for b in munged slurmctld slurmd sbatch squeue scontrol; do
  command -v "$b" >/dev/null || skip "$b not installed (tools/install-deps installs slurmctld slurmd slurm-client munge)"
done
fail() { echo "FAIL: $*" >&2; exit 1; }

# shellcheck source=tools/tests/slurm_cluster.sh
. "$src/tools/tests/slurm_cluster.sh"

# A cluster left by a run that was killed outright (no EXIT trap): stop it by its PIDs.
for old in /tmp/osslurm.*; do
  [ -f "$old/owner" ] || continue
  kill -0 "$(cat "$old/owner")" 2>/dev/null && continue
  slurm_cluster_stop "$old" >/dev/null 2>&1 || true
  rm -rf "$old"
done

rm -rf "$work" && mkdir -p "$work" && cd "$work"
cdir=$(mktemp -d /tmp/osslurm.XXXXXX)   # short: Unix socket paths are limited to 108 bytes
echo $$ >"$cdir/owner"
cleanup() {
  rc=$?
  slurm_cluster_stop "$cdir" >/dev/null 2>&1 || true
  if [ -f "$cdir/pids" ]; then
    while read -r name pid; do
      if kill -0 "$pid" 2>/dev/null; then echo "FAIL: $name (PID $pid) still running after stop" >&2; rc=1; fi
    done <"$cdir/pids"
  fi
  [ $rc -eq 0 ] && rm -rf "$cdir" || echo "cluster files kept in $cdir" >&2
  exit $rc
}
trap cleanup EXIT
slurm_cluster_start "$cdir" || fail "the one-node cluster did not start"
echo "cluster up: SLURM_CONF=$SLURM_CONF"
sinfo -h -o '%n %t %c' | grep -q "idle 2" || fail "node not idle with 2 CPUs: $(sinfo -h -o '%n %t %c')"

common=(--scenes aircraft,harbor --seeds 1-2 --cells 1/30,3/30,5/90 --duration 20 --resolution reduced --no-report)
slurm_opts=(--cpus-per-task 1 --max-parallel 2 --retries 1 --wait --timeout 480 --poll 1)

echo "== 1. an injected failure: retried, reported, merge names it"
"$exe" batch plan sweep "${common[@]}" -o plan >/dev/null
mkdir -p plan/fixtures/harbor-seed1.mcap        # task 2 (harbor/seed1) cannot write its fixture
set +e
"$exe" batch slurm plan "${slurm_opts[@]}" >slurm1.out 2>slurm1.err
rc=$?
set -e
cat slurm1.err
[ "$rc" -ne 0 ] || fail "--wait exited 0 with a failed task"
grep -q "^#SBATCH --array=0-3%2$" plan/slurm/array.sbatch || fail "array script: $(cat plan/slurm/array.sbatch)"
grep -q "task 2 (harbor/seed1) failed: .*Is a directory.*; log .*/plan/logs/task-2.log" slurm1.err ||
  fail "the failed task was not reported with its log"
[ "$(grep -c 'task 2 attempt [12] job' plan/logs/task-2.log)" -eq 2 ] || fail "task 2 not retried once: $(cat plan/logs/task-2.log)"
grep -q "task 2 (harbor/seed1): failed: " plan/logs/merge.log || fail "merge log does not name task 2: $(cat plan/logs/merge.log)"
grep -q "FAILED" slurm1.err || fail "final job states not reported"
[ ! -e plan/merged/seeds.md ] || fail "a merge with a missing task wrote outputs"

echo "== 2. fixed and re-submitted: only task 2 reruns"
rmdir plan/fixtures/harbor-seed1.mcap
"$exe" batch slurm plan "${slurm_opts[@]}" >slurm2.out 2>slurm2.err || { cat slurm2.err; fail "re-submission exited $?"; }
cat slurm2.err
for t in 0 1 3; do
  grep -q "result is current" "plan/logs/task-$t.log" || fail "task $t was not skipped on re-submission"
done
grep -q "task 2 (harbor/seed1): done" plan/logs/task-2.log || fail "task 2 did not complete"
grep -q "COMPLETED" slurm2.err || fail "final states not reported"

echo "== 3. identical to batch local and to the one-machine sweep"
"$exe" batch plan sweep "${common[@]}" -o lplan >/dev/null
"$exe" batch local lplan -j 2 >/dev/null 2>local.err || fail "batch local exited $?"
"$exe" sweep "${common[@]}" -o single >/dev/null 2>single.err || fail "sweep exited $?"
for other in lplan/merged single; do
  diff -r -x '*.mcap' -x 'runtime.*' plan/merged "$other" || fail "Slurm merge differs from $other"
done
echo "identical: $(find plan/merged -type f | wc -l) files"
echo "batch slurm: all checks passed"
