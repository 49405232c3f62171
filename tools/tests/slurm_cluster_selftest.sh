#!/bin/bash
# Self-test of tools/tests/slurm_cluster.sh: start a private one-node Slurm cluster, run a
# 4-task job array (throttled to 2 at once, task 2 exits 3) and a job depending on it, check
# states, exit codes, concurrency and ordering, stop the cluster and check that none of the
# daemons it started is still alive.
# Usage: slurm_cluster_selftest.sh [DIR]   (default: a fresh mktemp dir, removed on success)
# Exit 0 = pass, 1 = fail, 77 = skipped (not root, or Slurm/munge not installed).
set -u

case ${BASH_SOURCE[0]} in */*) here=${BASH_SOURCE[0]%/*} ;; *) here=. ;; esac
here=$(cd "$here" && pwd) || exit 1

# CI=true: the cluster tests must run (a skip there would hide a missing install step).
skip_rc=77
[ "${CI:-}" = true ] && skip_rc=1
if [ "${EUID:-$(id -u)}" != 0 ]; then
  echo "SKIP: must run as root (the test cluster runs slurmctld/slurmd/munged as root)"
  exit $skip_rc
fi
for cmd in munged slurmctld slurmd sbatch squeue scontrol sinfo scancel; do
  if ! command -v "$cmd" > /dev/null 2>&1; then
    echo "SKIP: $cmd not found (install slurmctld slurmd slurm-client munge: tools/install-deps)"
    exit $skip_rc
  fi
done

# shellcheck source-path=SCRIPTDIR source=slurm_cluster.sh
. "$here/slurm_cluster.sh"

if [ $# -ge 1 ]; then
  dir=$1
  own_dir=0
  mkdir -p "$dir" || exit 1
  dir=$(cd "$dir" && pwd -P)
else
  tmp=${TMPDIR:-/tmp}
  [ "${#tmp}" -le 40 ] || tmp=/tmp # socket paths under the cluster dir must stay short
  dir=$(mktemp -d "$tmp/slurm-selftest.XXXXXX") || exit 1
  own_dir=1
fi
trap 'slurm_cluster_stop "$dir"' EXIT

now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.2f", b - a }'; }
fail() {
  echo "FAIL: $*"
  if [ -n "${SLURM_CONF:-}" ] && [ -f "$SLURM_CONF" ]; then
    echo "--- squeue -t all"; timeout 15 squeue -t all -r -h -O 'JobArrayID:|,JobID:|,State:|,exit_code:|,Reason' 2>&1
  fi
  for f in "$dir"/log/slurmctld.log "$dir"/log/slurmd.log "$dir"/logs/*.log; do
    [ -f "$f" ] && { echo "--- $f"; tail -n 30 "$f"; }
  done
  echo "(cluster directory kept: $dir)"
  exit 1
}

# --- start ---
t0=$(now)
slurm_cluster_start "$dir" || fail "slurm_cluster_start failed"
t1=$(now)
[ "${SLURM_CONF:-}" = "$dir/slurm.conf" ] || fail "SLURM_CONF not exported (got '${SLURM_CONF:-}')"
state=$(sinfo -h -n localhost -o %t)
[ "$state" = idle ] || fail "node state '$state', expected idle"

# --- job array + dependent job ---
mkdir -p "$dir/logs" "$dir/jobs"
cat > "$dir/jobs/array.sh" << EOF
#!/bin/bash
#SBATCH --array=0-3%2
#SBATCH --output=$dir/logs/task-%a.log
#SBATCH --cpus-per-task=1
#SBATCH --job-name=selftest-array
echo "task=\$SLURM_ARRAY_TASK_ID array_job=\$SLURM_ARRAY_JOB_ID"
echo "start=\$(date +%s.%N)"
sleep 2
echo "end=\$(date +%s.%N)"
[ "\$SLURM_ARRAY_TASK_ID" = 2 ] && exit 3
exit 0
EOF
t2=$(now)
out=$(sbatch --parsable "$dir/jobs/array.sh") || fail "sbatch of the array failed"
# --parsable prints "JOBID" or "JOBID;CLUSTER" (only for multi-cluster/federation setups).
[[ $out =~ ^[0-9]+(\;[A-Za-z0-9_-]+)?$ ]] || fail "unexpected 'sbatch --parsable' output '$out'"
jid=${out%%;*}
# shellcheck disable=SC2016 # $(date) is for the job's shell
out=$(sbatch --parsable --dependency="afterany:$jid" --job-name=selftest-dep \
  --output="$dir/logs/dep.log" --wrap 'echo "dep start=$(date +%s.%N)"') || fail "sbatch of the dependent job failed"
[[ $out =~ ^[0-9]+(\;[A-Za-z0-9_-]+)?$ ]] || fail "unexpected 'sbatch --parsable' output '$out'"
dep=${out%%;*}
echo "submitted array job $jid and dependent job $dep"

# Follow both until every task has a final state. 'squeue -t all' keeps listing finished jobs
# until MinJobAge has passed; -r puts each pending array task on its own line. exit_code is
# the raw wait() status (exit code * 256 + signal).
final='^(COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY|PREEMPTED|BOOT_FAIL|DEADLINE)$'
max_running=0
done_all=0
for _ in $(seq 240); do
  lines=$(squeue -h -r -t all -j "$jid,$dep" -O 'JobArrayID:|,State:|,exit_code') || fail "squeue failed"
  running=$(grep -c '|RUNNING|' <<< "$lines")
  [ "$running" -gt "$max_running" ] && max_running=$running
  n=0
  nfinal=0
  while IFS='|' read -r id st code; do
    [ -n "$id" ] || continue
    n=$((n + 1))
    [[ $st =~ $final ]] && nfinal=$((nfinal + 1))
  done <<< "$lines"
  if [ "$n" = 5 ] && [ "$nfinal" = 5 ]; then
    done_all=1
    break
  fi
  sleep 0.25
done
t3=$(now)
[ "$done_all" = 1 ] || fail "jobs not finished after 60 s; last squeue output:
$lines"
echo "final squeue -h -r -t all -j $jid,$dep -O 'JobArrayID:|,State:|,exit_code':"
sed 's/ *$//; s/^/  /' <<< "$lines"

# --- assertions: per-task state and exit code, from squeue and from scontrol ---
for task in 0 1 2 3; do
  if [ "$task" = 2 ]; then want_state=FAILED want_code=3; else want_state=COMPLETED want_code=0; fi
  line=$(grep "^${jid}_${task} *|" <<< "$lines") || fail "task $task missing from squeue output"
  IFS='|' read -r _ st code <<< "$line"
  st=${st%% *}
  code=${code%% *}
  [ "$st" = "$want_state" ] || fail "task $task: squeue state '$st', expected $want_state"
  [ $((code >> 8)) = "$want_code" ] || fail "task $task: squeue exit_code '$code', expected exit $want_code"
  log="$dir/logs/task-$task.log"
  grep -qx "task=$task array_job=$jid" "$log" 2> /dev/null || fail "$log does not show SLURM_ARRAY_TASK_ID=$task"
done
# scontrol show job -o ID: one line per array element (already finished ones too, until MinJobAge).
sc=$(scontrol show job -o "$jid") || fail "scontrol show job $jid failed"
[ "$(grep -c "ArrayJobId=$jid " <<< "$sc")" = 4 ] || fail "scontrol show job -o $jid: expected 4 lines, got:
$sc"
while read -r l; do
  task=$(sed -n 's/.* ArrayTaskId=\([0-9]*\) .*/\1/p' <<< "$l")
  [ -n "$task" ] || continue
  st=$(sed -n 's/.* JobState=\([A-Z_]*\) .*/\1/p' <<< "$l")
  code=$(sed -n 's/.* ExitCode=\([0-9]*:[0-9]*\) .*/\1/p' <<< "$l")
  if [ "$task" = 2 ]; then want="FAILED 3:0"; else want="COMPLETED 0:0"; fi
  [ "$st $code" = "$want" ] || fail "scontrol: task $task is '$st $code', expected '$want'"
done <<< "$sc"

# --- concurrency (%2 throttle, 2 CPUs) and the dependency ordering, from the task logs ---
starts=() ends=()
for task in 0 1 2 3; do
  starts+=("$(sed -n 's/^start=//p' "$dir/logs/task-$task.log")")
  ends+=("$(sed -n 's/^end=//p' "$dir/logs/task-$task.log")")
done
overlap=$(awk -v s="${starts[*]}" -v e="${ends[*]}" 'BEGIN {
  n = split(s, a, " "); split(e, b, " "); best = 0
  for (i = 1; i <= n; i++) { c = 0; for (j = 1; j <= n; j++) if (a[j] <= a[i] && b[j] > a[i]) c++; if (c > best) best = c }
  print best }')
[ "$overlap" = 2 ] || fail "expected exactly 2 array tasks running at once, saw at most $overlap"
[ "$max_running" -le 2 ] || fail "squeue showed $max_running tasks running at once (throttle is 2)"
dep_line=$(grep "^$dep *|" <<< "$lines")
[ "$(cut -d'|' -f2 <<< "$dep_line" | tr -d ' ')" = COMPLETED ] || fail "dependent job: '$dep_line'"
dep_start=$(sed -n 's/^dep start=//p' "$dir/logs/dep.log")
[ -n "$dep_start" ] || fail "dependent job did not run ($dir/logs/dep.log)"
last_end=$(printf '%s\n' "${ends[@]}" | sort -n | tail -n 1)
awk -v d="$dep_start" -v e="$last_end" 'BEGIN { exit !(d >= e) }' \
  || fail "dependent job started at $dep_start, before the last array task ended at $last_end"

# --- stop ---
t4=$(now)
slurm_cluster_stop "$dir"
t5=$(now)
while read -r name pid; do
  if slurm_cluster__is "$pid" "$name"; then
    fail "$name (pid $pid) still alive after slurm_cluster_stop"
  fi
done < "$dir/pids"
[ "$(wc -l < "$dir/pids")" -ge 3 ] || fail "expected at least 3 recorded daemons in $dir/pids"
for pid in $(pgrep -x slurmstepd); do
  if slurm_cluster__uses_dir "$pid" "$dir"; then fail "slurmstepd (pid $pid) of this cluster still alive"; fi
done
slurm_cluster_stop "$dir" # idempotent

echo "timings: start $(elapsed "$t0" "$t1") s, 4-task array (2 s per task, %2) + dependent job $(elapsed "$t2" "$t3") s, stop $(elapsed "$t4" "$t5") s"
trap - EXIT
[ "$own_dir" = 1 ] && rm -rf "$dir"
echo "PASS: slurm_cluster selftest"
exit 0
