# shellcheck shell=bash
# Private one-node Slurm cluster on loopback, for ctest shell tests. Source this file (bash).
#
#   slurm_cluster_start DIR   munged + slurmctld + slurmd, all state/sockets/logs under DIR; exports
#                             SLURM_CONF=DIR/slurm.conf; returns once the node is idle (60 s at most),
#                             else prints the daemon logs, stops what it started and returns 1.
#   slurm_cluster_stop DIR    cancels remaining jobs (bounded wait), SIGKILLs leftover job processes
#                             of this cluster, then stops the daemons recorded in DIR/pids (SIGTERM,
#                             up to 10 s, SIGKILL); idempotent. Use: trap 'slurm_cluster_stop "$dir"' EXIT
#
# Call slurm_cluster_start in the test's own shell (not in $(...) or a pipeline): it must export
# SLURM_CONF there, and the daemons are that shell's background children so stop can reap them.
# It also unsets inherited SLURM_*/SBATCH_*/SQUEUE_*/... client variables (e.g. from an outer Slurm
# job, whose SLURM_WORKING_CLUSTER would send our commands to the other cluster).
# SLURM_CLUSTER_EXTRA_CONF, if set, is appended to slurm.conf (a repeated key overrides the
# default, e.g. SLURM_CLUSTER_EXTRA_CONF=MinJobAge=30).
# Needs root (SlurmUser=root, munged as root) and the Debian packages slurmctld slurmd slurm-client
# munge (tools/install-deps). Nothing in /etc/slurm, /etc/munge, /run/munge or /var is used or
# changed, and no service is started. tools/tests/slurm_cluster_selftest.sh is a complete example.
#
# Cluster: ClusterName=orthotest, SlurmctldHost=localhost(127.0.0.1), node "localhost" (NodeAddr
# 127.0.0.1, CPUs=2), partition "debug" (default), two free TCP ports picked at start (listening on
# 127.0.0.1 only when `hostname` resolves to 127.x, as here; else on all addresses), select/cons_tres
# with CR_CPU (two 1-CPU tasks at once), backfill scheduler every second (a job starts within ~1 s),
# MinJobAge=3600 (finished jobs stay visible to squeue/scontrol for an hour), KillWait=5, no
# accounting database, job completion records in DIR/log/jobcomp.txt. Logs: DIR/log/{munged.log,
# slurmctld.log,slurmd.log} (slurmd.log also has the slurmstepd messages of every job).
#
# Findings (Slurm 22.05.8, munge 0.5.15, Debian 12; commands and output as observed here):
#
# * sacct does not work without slurmdbd. With AccountingStorageType=accounting_storage/none:
#     $ sacct -j 1 --format=JobID,State,ExitCode -P -n
#     Slurm accounting storage is disabled               (on stderr; nothing on stdout; exit status 1)
#   accounting_storage/filetxt no longer exists. With JobCompType=jobcomp/filetxt (set here)
#   "sacct -c" reads JobCompLoc, but only by raw job id: it does not understand array ids and
#   complains about the array fields:
#     $ sacct -c -j 1_2 --format=JobID,State,ExitCode -P -n
#     1|COMPLETED|0:0          <- raw JobId 1, which is the array's task 3 here, not task 2
#     sacct: error: Unknown type ArrayJobId: 1           (stderr, a pair of these per record)
#     sacct: error: Unknown type ArrayTaskId: 3
#   So do not use sacct with this setup. DIR/log/jobcomp.txt itself is a permanent record, one
#   line per finished job or array task, still there after MinJobAge (grep "ArrayJobId=ID "):
#     JobId=5 UserId=root(0) GroupId=root(0) Name=arr JobState=FAILED Partition=debug ... ArrayJobId=1
#       ArrayTaskId=2 DerivedExitCode=0:0 ExitCode=3:0
#
# * To follow an array job to completion and learn each task's final state and exit code, poll
#     $ squeue -h -r -t all -j ID -O 'JobArrayID:|,State:|,exit_code'
#   until it prints one line per task and every State is final (COMPLETED FAILED CANCELLED TIMEOUT
#   NODE_FAIL OUT_OF_MEMORY PREEMPTED BOOT_FAIL DEADLINE). Array job 1 = --array=0-3%2 where task 2
#   exits 3 (lines come in no particular order; the last field is padded with blanks):
#     while running:        when done:
#       1_2|PENDING|0         1_3|COMPLETED|0
#       1_3|PENDING|0         1_0|COMPLETED|0
#       1_0|RUNNING|0         1_1|COMPLETED|0
#       1_1|RUNNING|0         1_2|FAILED|768
#   exit_code is the raw wait() status: exit code = value >> 8 (768 -> 3), signal = value & 127.
#   -t all is needed: plain squeue drops finished jobs (squeue -h -j 1 prints nothing, exit 0, once
#   all tasks are done). -r puts each pending task on its own line; without it they share one:
#     $ squeue -h -j 1 -o '%i %T'  ->  1_[2-3%2] PENDING / 1_1 RUNNING / 1_0 RUNNING
#   ',Reason' adds e.g. JobArrayTaskLimit (held back by %2), Dependency, NonZeroExitCode. The same
#   per task, with the usual "code:signal" exit code, one line per array element:
#     $ scontrol show job -o ID
#     JobId=5 ArrayJobId=1 ArrayTaskId=2 ArrayTaskThrottle=2 JobName=arr ... JobState=FAILED
#       Reason=NonZeroExitCode ... ExitCode=3:0 RunTime=00:00:02 ...
#     JobId=1 ArrayJobId=1 ArrayTaskId=2-3%2 ... JobState=PENDING ... ExitCode=0:0 ...
#   (still-pending tasks share one line). The raw JobId equal to the array id ends up on the last
#   task to start (task 3 above), so key on ArrayTaskId, never on the raw JobId. One task:
#     $ squeue -h -t all -j 1_2 -o '%i %T'              ->  1_2 FAILED
#     $ scontrol show job -o 1_2                        ->  ... JobState=FAILED ... ExitCode=3:0 ...
#   Both work only until MinJobAge has passed since the job ended; after that the job is purged:
#     $ squeue -h -r -t all -j 1 -O ...   ->  slurm_load_jobs error: Invalid job id specified
#   (stderr, exit status 1; scontrol show job: same). Only jobcomp.txt remains then.
#
# * sbatch --parsable prints just the job id ("1"), or "ID;CLUSTER" on multi-cluster setups: use
#   ${out%%;*}. For an array it is the array job id; the tasks are ID_0, ID_1, ... In the script,
#   #SBATCH --array=0-3%2, --output=DIR/logs/task-%a.log (%a = task id) and --cpus-per-task=1 work:
#   SLURM_ARRAY_TASK_ID and SLURM_ARRAY_JOB_ID are set, at most 2 tasks run at once (exactly 2 here),
#   a task exiting 3 ends FAILED with ExitCode=3:0, and sbatch --dependency=afterany:ID waits
#   (Reason=Dependency) for all tasks, failed ones included, then runs.
#
# * Pitfalls met:
#   - munged checks every directory above its key, socket and seed files and refuses group/world-
#     writable ones without the sticky bit ("Error: PRNG seed dir is insecure: group-writable
#     permissions without sticky bit set on ..."), and a key readable by group/other ("Error:
#     Keyfile is insecure: ... should not be readable or writable by group (perms=0644)"); --force
#     turns both into warnings (the key is made 0400 anyway). munged -F logs to stderr (here
#     DIR/log/munged.log), including "Unauthorized credential for client UID=0 GID=0": harmless.
#   - Unix socket paths are limited to 108 bytes: munged fails ("Exceeded maximum length of 108
#     bytes for socket pathname"), and, worse, with DIR longer than ~70 characters slurmd starts but
#     every job fails ("_create_socket: Unix socket path '.../spool/localhost_1.4294967291' is too
#     long", job "launch failed requeued held"). So start refuses a DIR over 64 characters: prefer
#     mktemp -d under /tmp to a deep ctest binary directory.
#   - SlurmctldHost must name this host: with another name slurmctld keeps running but never serves
#     ("error: This host (vm/vm) not a valid controller") and start times out. `hostname -s` works;
#     "localhost" is always accepted, so it is used. slurmd gets -N localhost, so the node name does
#     not depend on the host name either.
#   - CommunicationParameters=NoCtldInAddrAny,NoInAddrAny bind to what gethostname() resolves to,
#     not to NodeAddr/SlurmctldHost, so they are only set when that is a 127.x address.
#   - CPUs=2 alone makes Slurm assume 2 sockets x 1 core: slurmd logs "Node configuration differs
#     from hardware" (harmless); SlurmdParameters=config_overrides keeps the node usable on a
#     1-CPU machine. proctrack/linuxproc + task/none: no cgroup plugin, no cgroup.conf, no cgroup
#     complaints. slurmctld logs "Could not open ... state file" errors on a fresh state dir, and
#     "Configured MailProg is invalid" unless MailProg is set: harmless.
#   - With the controller dead every client command hangs ~10 s (MessageTimeout) before failing, and
#     a slurmd still trying to register ignores SIGTERM for as long.
#   - slurmctld exits with "fatal: slurm_init_msg_engine_port error Address already in use" when its
#     port got taken between the check and the bind: start then retries with new ports.
#   - slurmstepd (one per running job) is not a child of slurmd and survives it, and so do the job's
#     processes: stop cancels the jobs first (a job ignoring SIGTERM takes KillWait=5 s more), then
#     kills stragglers. A SIGTERM/SIGINT to the test still runs its EXIT trap (checked); a SIGKILL
#     does not: the daemons are children of the test shell, so a kill of the whole process tree
#     (ctest's timeout handling) should reach them, but a running job's slurmstepd would survive.
#   - Two clusters (two selftests at once) run side by side without trouble: own ports, own munge
#     socket and key, own SLURM_CONF.
#   Timings here (2 CPUs, idle machine): start 0.6-1.3 s; the selftest's 4-task array (2 s sleep per
#   task, %2) plus an afterany dependent job 5.8-7.5 s (4 s of sleeping; the first tasks start in
#   <0.3 s, later waves ~1 s after a slot frees, the dependent job ~1 s after the array); stop 0.6-1 s.

slurm_cluster__say() { echo "slurm_cluster: $*" >&2; }

# True when nothing listens on TCP port $1 (any address) and 127.0.0.1:$1 refuses connections.
slurm_cluster__port_free() {
  local port=$1
  if command -v ss > /dev/null 2>&1 && ss -Hltn "sport = :$port" 2> /dev/null | grep -q .; then
    return 1
  fi
  if (exec 3<> "/dev/tcp/127.0.0.1/$port") 2> /dev/null; then
    return 1
  fi
  return 0
}

# Prints N distinct free ports from 20000-32767 (below the usual ephemeral range 32768-60999).
slurm_cluster__free_ports() {
  local n=$1 found=() port tries=0 p dup
  while [ "${#found[@]}" -lt "$n" ]; do
    tries=$((tries + 1))
    if [ "$tries" -gt 500 ]; then
      slurm_cluster__say "no free TCP port found"
      return 1
    fi
    port=$((20000 + RANDOM % 12768))
    dup=0
    for p in "${found[@]}"; do [ "$p" = "$port" ] && dup=1; done
    [ "$dup" = 0 ] || continue
    slurm_cluster__port_free "$port" && found+=("$port")
  done
  echo "${found[@]}"
}

# True when PID $1 exists and is not a zombie. (Builtins only: forks are slow in some VMs.)
slurm_cluster__alive() {
  local stat
  [ -n "$1" ] || return 1
  { read -r stat < "/proc/$1/stat"; } 2> /dev/null || return 1
  case ${stat##*) } in Z* | X*) return 1 ;; esac
  return 0
}

# True when PID $1 is alive and its command name is $2 (guards against PID reuse).
slurm_cluster__is() {
  local comm
  slurm_cluster__alive "$1" || return 1
  { read -r comm < "/proc/$1/comm"; } 2> /dev/null || return 1
  [ "$comm" = "$2" ]
}

# slurm_cluster__record DIR NAME PID: appends "NAME PID" to DIR/pids, then waits (5 s at most)
# until the forked background shell has exec'ed NAME.
slurm_cluster__record() {
  local dir=$1 name=$2 pid=$3
  echo "$name $pid" >> "$dir/pids"
  for _ in $(seq 50); do
    slurm_cluster__alive "$pid" || return 1
    slurm_cluster__is "$pid" "$name" && return 0
    sleep 0.1
  done
  return 1
}

# True when process $1 has a file under directory $2 open (e.g. our slurmstepd: DIR/log/slurmd.log).
slurm_cluster__uses_dir() {
  local fd
  for fd in "/proc/$1/fd/"*; do
    case $(readlink "$fd" 2> /dev/null) in "$2"/*) return 0 ;; esac
  done
  return 1
}

slurm_cluster__dump_logs() {
  local dir=$1 f
  # With -D, slurmctld.out/slurmd.out hold what slurmctld.log/slurmd.log do, plus early errors.
  for f in "$dir/log/munged.log" "$dir/log/slurmctld.out" "$dir/log/slurmd.out"; do
    [ -f "$f" ] || continue
    echo "===== $f (last 40 lines) =====" >&2
    tail -n 40 "$f" >&2
  done
}

slurm_cluster_start() {
  local dir=${1:?usage: slurm_cluster_start DIR}
  local cmd ports ctld_port slurmd_port pid name attempt rc
  if [ "${EUID:-$(id -u)}" != 0 ]; then
    slurm_cluster__say "must run as root"
    return 1
  fi
  for cmd in munged slurmctld slurmd sinfo scancel squeue; do
    if ! command -v "$cmd" > /dev/null 2>&1; then
      slurm_cluster__say "$cmd not found (install slurmctld slurmd slurm-client munge: tools/install-deps)"
      return 1
    fi
  done
  mkdir -p "$dir" || return 1
  dir=$(cd "$dir" && pwd -P) || return 1
  # Unix socket paths are limited to 108 bytes; the longest one is slurmstepd's
  # DIR/spool/localhost_JOBID.4294967291 (with a longer DIR, every job ends up
  # "launch failed requeued held").
  if [ "${#dir}" -gt 64 ]; then
    slurm_cluster__say "$dir is ${#dir} characters long, at most 64 fit the socket paths under it; use e.g. \$(mktemp -d)"
    return 1
  fi
  if [ -s "$dir/pids" ]; then
    slurm_cluster__say "$dir/pids exists: stopping the cluster recorded there first"
    slurm_cluster_stop "$dir"
  fi
  mkdir -p "$dir/state" "$dir/spool" "$dir/log" "$dir/munge" || return 1
  : > "$dir/pids" || return 1
  # munged wants no group/world-writable (non-sticky) directory on its paths, and a socket
  # directory everyone can traverse.
  chmod 0755 "$dir" "$dir/log" "$dir/spool" && chmod 0711 "$dir/munge" && chmod 0700 "$dir/state" || return 1

  # --- munged, with a fresh key and a private socket ---
  rm -f "$dir/munge/munge.key" "$dir/munge/munge.socket"
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1 count=1024 status=none || return 1
  chmod 0400 "$dir/munge/munge.key" || return 1
  munged --foreground --force \
    --socket="$dir/munge/munge.socket" \
    --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" \
    --seed-file="$dir/munge/munged.seed" \
    < /dev/null > "$dir/log/munged.log" 2>&1 &
  pid=$!
  slurm_cluster__record "$dir" munged "$pid" || true
  for _ in $(seq 100); do
    [ -S "$dir/munge/munge.socket" ] && break
    slurm_cluster__is "$pid" munged || break
    sleep 0.1
  done
  if [ ! -S "$dir/munge/munge.socket" ]; then
    slurm_cluster__say "munged did not start"
    slurm_cluster__dump_logs "$dir"
    slurm_cluster_stop "$dir"
    return 1
  fi

  # --- slurm.conf, slurmctld, slurmd (new ports and another try if one got taken meanwhile) ---
  for name in $(compgen -e); do
    case $name in
      SLURM_CLUSTER_*) ;;
      SLURM_* | SBATCH_* | SALLOC_* | SRUN_* | SQUEUE_* | SINFO_* | SACCT_* | SCONTROL_* | SCANCEL_*) unset "$name" ;;
    esac
  done
  export SLURM_CONF="$dir/slurm.conf"
  for attempt in 1 2 3; do
    ports=$(slurm_cluster__free_ports 2) || break
    read -r ctld_port slurmd_port <<< "$ports"
    slurm_cluster__write_conf "$dir" "$ctld_port" "$slurmd_port" || break
    rc=0
    slurm_cluster__launch "$dir" || rc=$?
    case $rc in
      0) return 0 ;;
      2) slurm_cluster__say "port $ctld_port or $slurmd_port got taken (attempt $attempt); trying other ports" ;;
      *) break ;;
    esac
  done
  slurm_cluster__dump_logs "$dir"
  slurm_cluster_stop "$dir"
  return 1
}

# slurm_cluster__write_conf DIR CTLD_PORT SLURMD_PORT: writes DIR/slurm.conf.
slurm_cluster__write_conf() {
  local dir=$1 ctld_port=$2 slurmd_port=$3 comm="#CommunicationParameters="
  # No*InAddrAny make the daemons bind to what gethostname() resolves to (not to NodeAddr): only
  # use them when that is a loopback address, else they would listen where nobody connects.
  case $(getent ahostsv4 "$(hostname)" 2> /dev/null | awk '{ print $1; exit }') in
    127.*) comm="CommunicationParameters=NoCtldInAddrAny,NoInAddrAny" ;;
  esac
  cat > "$dir/slurm.conf" << EOF || return 1
# Generated by tools/tests/slurm_cluster.sh: private one-node test cluster, everything under $dir
ClusterName=orthotest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
$comm
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.txt
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SlurmdParameters=config_overrides
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0,bf_interval=1
ReturnToService=2
MinJobAge=3600
KillWait=5
InactiveLimit=0
SlurmdTimeout=300
NodeName=localhost NodeHostname=$(hostname) NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
EOF
  if [ -n "${SLURM_CLUSTER_EXTRA_CONF:-}" ]; then
    printf '# From SLURM_CLUSTER_EXTRA_CONF:\n%s\n' "$SLURM_CLUSTER_EXTRA_CONF" >> "$dir/slurm.conf" || return 1
  fi
}

# slurm_cluster__launch DIR: starts slurmctld and slurmd on DIR/slurm.conf, waits (60 s at most)
# for the node to be idle. Returns 0 when idle, 2 when a daemon died because its port was
# taken (both are killed then), 1 on any other failure.
slurm_cluster__launch() {
  local dir=$1 ctld slurmd state=""
  slurmctld -D -f "$dir/slurm.conf" < /dev/null > "$dir/log/slurmctld.out" 2>&1 &
  ctld=$!
  slurm_cluster__record "$dir" slurmctld "$ctld" || true
  slurmd -D -f "$dir/slurm.conf" -N localhost < /dev/null > "$dir/log/slurmd.out" 2>&1 &
  slurmd=$!
  slurm_cluster__record "$dir" slurmd "$slurmd" || true
  for _ in $(seq 200); do
    # Check the daemons first: with the controller gone, sinfo would hang ~10 s.
    if ! slurm_cluster__is "$ctld" slurmctld || ! slurm_cluster__is "$slurmd" slurmd; then
      if grep -qs 'Address already in use' "$dir/log/slurmctld.out" "$dir/log/slurmd.out"; then
        # SIGKILL: a slurmd blocked registering with a wrong peer ignores SIGTERM for ~10 s.
        # (Braces + 2>/dev/null also silence bash's "PID Killed ..." job notice.)
        {
          if slurm_cluster__is "$slurmd" slurmd; then kill -KILL "$slurmd" || true; fi
          if slurm_cluster__is "$ctld" slurmctld; then kill -KILL "$ctld" || true; fi
          wait "$slurmd" "$ctld" || true
        } 2> /dev/null
        return 2
      fi
      slurm_cluster__is "$ctld" slurmctld || slurm_cluster__say "slurmctld (pid $ctld) died during start-up"
      slurm_cluster__is "$slurmd" slurmd || slurm_cluster__say "slurmd (pid $slurmd) died during start-up"
      return 1
    fi
    state=$(timeout 5 sinfo -h -n localhost -o %t 2> /dev/null) || state=""
    [ "$state" = idle ] && return 0
    sleep 0.25
  done
  slurm_cluster__say "node not idle after 60 s (sinfo state: '$state')"
  return 1
}

# slurm_cluster__terminate NAME PID [NAME PID ...]: SIGTERM, in the order given, each PID still
# alive under command name NAME; wait up to 10 s; SIGKILL the rest; reap our own children.
slurm_cluster__terminate() {
  local names=() pids=() i alive
  while [ $# -ge 2 ]; do
    names+=("$1")
    pids+=("$2")
    shift 2
  done
  for i in "${!pids[@]}"; do
    slurm_cluster__is "${pids[$i]}" "${names[$i]}" && { kill -TERM "${pids[$i]}" 2> /dev/null || true; }
  done
  for _ in $(seq 100); do
    alive=0
    for i in "${!pids[@]}"; do
      slurm_cluster__is "${pids[$i]}" "${names[$i]}" && alive=1
    done
    [ "$alive" = 0 ] && break
    sleep 0.1
  done
  for i in "${!pids[@]}"; do
    slurm_cluster__is "${pids[$i]}" "${names[$i]}" \
      && slurm_cluster__say "${names[$i]} (pid ${pids[$i]}) ignored SIGTERM for 10 s: SIGKILL"
  done
  # Then reap those that are this shell's background children, so no zombies are left.
  # (Braces + 2>/dev/null also silence bash's "PID Killed ..." job notice.)
  {
    for i in "${!pids[@]}"; do
      slurm_cluster__is "${pids[$i]}" "${names[$i]}" && { kill -KILL "${pids[$i]}" || true; }
    done
    for i in "${!pids[@]}"; do wait "${pids[$i]}" || true; done
  } 2> /dev/null
  return 0
}

slurm_cluster_stop() {
  local dir=${1:?usage: slurm_cluster_stop DIR}
  local name pid pids=() names=() i port="" marker kid queue=() stray=() left f args=()
  [ -f "$dir/pids" ] || return 0
  dir=$(cd "$dir" && pwd -P) || return 0 # start recorded the physical path
  while read -r name pid; do
    [ -n "$pid" ] || continue
    names+=("$name")
    pids+=("$pid")
  done < "$dir/pids"
  # Cancel all jobs while the controller is up and give them (bounded) time to end, so no job
  # processes outlive the cluster.
  if [ -f "$dir/slurm.conf" ]; then
    port=$(sed -n 's/^SlurmctldPort=//p' "$dir/slurm.conf")
    for i in "${!pids[@]}"; do
      if [ "${names[$i]}" != slurmctld ] || ! slurm_cluster__is "${pids[$i]}" slurmctld; then continue; fi
      SLURM_CONF="$dir/slurm.conf" timeout 10 scancel --partition=debug > /dev/null 2>&1 || true
      for _ in $(seq 30); do
        left=$(SLURM_CONF="$dir/slurm.conf" timeout 5 squeue -h -t PD,CF,R,S,CG -o %i 2> /dev/null) || break
        [ -z "$left" ] && break
        sleep 0.5
      done
    done
  fi
  # Stragglers: our slurmstepd processes (not children of slurmd: found by their open files
  # under DIR), their descendants (job scripts), and processes whose environment names this
  # cluster (SLURM_WORKING_CLUSTER=orthotest:127.0.0.1:PORT:..., set by sbatch in every job).
  for pid in $(pgrep -x slurmstepd 2> /dev/null); do
    if slurm_cluster__uses_dir "$pid" "$dir"; then queue+=("$pid"); fi
  done
  if [ -n "$port" ]; then
    marker="SLURM_WORKING_CLUSTER=$(sed -n 's/^ClusterName=//p' "$dir/slurm.conf"):127.0.0.1:$port:"
    while read -r f; do
      pid=${f#/proc/}
      pid=${pid%/environ}
      [ "$pid" = "$$" ] || [ "$pid" = "${BASHPID:-$$}" ] || queue+=("$pid")
    done < <(grep -lzF -- "$marker" /proc/[0-9]*/environ 2> /dev/null)
  fi
  # These got their chance (scancel, KillWait): SIGSTOP them all first, so none can fork or
  # respawn while we walk the tree, then SIGKILL.
  while [ "${#queue[@]}" -gt 0 ]; do
    pid=${queue[0]}
    queue=("${queue[@]:1}")
    case " ${pids[*]} ${stray[*]} " in *" $pid "*) continue ;; esac
    slurm_cluster__alive "$pid" || continue
    kill -STOP "$pid" 2> /dev/null || continue
    stray+=("$pid")
    for kid in $(pgrep -P "$pid" 2> /dev/null); do queue+=("$kid"); done
  done
  if [ "${#stray[@]}" -gt 0 ]; then
    slurm_cluster__say "killing ${#stray[@]} leftover job process(es) of $dir"
    kill -KILL "${stray[@]}" 2> /dev/null || true
  fi
  # Then the daemons, in reverse start order: slurmd, slurmctld, munged.
  for ((i = ${#pids[@]} - 1; i >= 0; i--)); do args+=("${names[$i]}" "${pids[$i]}"); done
  slurm_cluster__terminate "${args[@]}"
}
