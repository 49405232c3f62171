# Sourced by the TypeScript interop tests (run_interop.sh, run_rewrite.sh, and the ros/,
# run/ interop scripts): npm-installs package.json (the official TypeScript MCAP libraries
# and Foxglove's ROS serialisers) into the build tree, once per version of package.json,
# and copies the scripts beside node_modules (node resolves imports from a script's folder).
# Needs $src (this folder) and $npm_dir; exits 77 (ctest SKIP_RETURN_CODE) only when npm
# cannot install the packages, and under CI=true exits 1 instead, naming what is missing:
# CI must run these tests, and a skip (counted as passed by ctest) would hide a missing
# install step. Nothing may hang: npm gets 240 s (a registry that drops packets would
# otherwise hold it for 15 minutes), a failed install is remembered so the other interop
# tests skip (under CI: fail) at once, and every `node` call of the sourcing script is
# stopped after 60 s with what it was doing printed, and run again (see node()).
npm_skip() {
  if [ "${CI:-}" = true ]; then
    echo "FAIL (CI=true: this test must run, not skip): $*" >&2
    exit 1
  fi
  echo "SKIP: $*"
  exit 77
}
mkdir -p "$npm_dir" || exit 1
cp "$src/package.json" "$src"/*.mjs "$npm_dir/" || exit 1
stamp="$npm_dir/node_modules/.orthosonar-installed"
unavailable="$npm_dir/.orthosonar-npm-unavailable"
if [ ! -f "$stamp" ] || ! cmp -s "$npm_dir/package.json" "$stamp"; then
  if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
    npm_skip "$(command -v npm >/dev/null 2>&1 || echo 'npm ')$(command -v node >/dev/null 2>&1 || echo 'node ')not installed; cannot fetch the TypeScript MCAP libraries (tools/install-deps installs npm)"
  fi
  if [ -f "$unavailable" ] && cmp -s "$npm_dir/package.json" "$unavailable"; then
    npm_skip "npm could not install the packages earlier in this build (see $npm_dir/npm-install.log)"
  fi
  if ! (cd "$npm_dir" && timeout 240 npm install --no-audit --no-fund --no-package-lock --fetch-timeout=60000 \
          --fetch-retries=1 >npm-install.log 2>&1); then
    cp "$npm_dir/package.json" "$unavailable"
    tail -5 "$npm_dir/npm-install.log"
    npm_skip "npm cannot install the packages within 240 s (see $npm_dir/npm-install.log)"
  fi
  rm -f "$unavailable"
  cp "$npm_dir/package.json" "$stamp"
fi
node_diagnose() {
  # What a stuck node is doing, read from /proc (Linux): load, memory, the process's CPU
  # time sampled twice 2 s apart (spinning or blocked), and every thread's name, state,
  # kernel wait channel and current system call. $1: the pid of the `timeout` running node.
  for p in $(cat "/proc/$1/task/$1/children" 2>/dev/null); do
    echo "  load: $(cat /proc/loadavg); $(grep -E '^(MemAvailable|SwapFree)' /proc/meminfo | tr -s ' ' | tr '\n' ' ')"
    t0=$(cut -d' ' -f14,15 "/proc/$p/stat" 2>/dev/null)
    sleep 2
    t1=$(cut -d' ' -f14,15 "/proc/$p/stat" 2>/dev/null)
    echo "  pid $p: user/system clock ticks $t0 -> $t1 over 2 s; rss $(grep VmRSS "/proc/$p/status" 2>/dev/null | tr -s ' ')"
    for t in /proc/"$p"/task/*; do
      echo "  thread ${t##*/} $(cat "$t/comm" 2>/dev/null): $(grep '^State' "$t/status" 2>/dev/null | cut -f2)," \
        "wchan $(cat "$t/wchan" 2>/dev/null), syscall $(cut -d' ' -f1 "$t/syscall" 2>/dev/null)"
    done
  done
}
node() {
  # Every script these tests run finishes in a few seconds. A node that has not finished
  # in 60 s is stuck outside our code (seen twice in CI, never here: the zstd rewrite once,
  # the nosummary rewrite twice running, each fine on every rerun). Before it is stopped
  # the log gets what it was doing: its threads' states and system calls from /proc, and
  # its JavaScript stack when its event loop still answers a diagnostic-report signal.
  # Then it runs again, up to three attempts, the second with V8's --single-threaded (no
  # background compilation or GC threads), so a stuck run says whether V8's threads are
  # involved. A script that fails, or sticks three times, still fails the test.
  node_attempt=1
  while :; do
    node_reports=$(mktemp -d "$npm_dir/node-report.XXXXXX") || return 1
    node_v8=
    [ $node_attempt -ne 2 ] || node_v8=--single-threaded
    node_flag="$node_reports/finished"
    node_diag="$node_reports/diagnosis.txt"
    timeout -s USR2 -k 15 60 node $node_v8 --report-on-signal --report-signal=SIGUSR2 \
      --report-directory="$node_reports" "$@" &
    node_timeout_pid=$!
    # The watchdog writes to a file, never to the test's output (ctest would wait for it),
    # and leaves within a second of node's end.
    (
      waited=0
      while [ ! -f "$node_flag" ] && [ $waited -lt 55 ]; do sleep 1; waited=$((waited + 1)); done
      [ -f "$node_flag" ] || node_diagnose $node_timeout_pid
    ) >"$node_diag" 2>&1 </dev/null &
    node_watchdog_pid=$!
    wait $node_timeout_pid
    node_rc=$?
    : >"$node_flag"
    wait $node_watchdog_pid
    if [ $node_rc -ne 124 ] && [ $node_rc -ne 137 ]; then
      rm -rf "$node_reports"
      return $node_rc
    fi
    echo "node ${node_v8:+$node_v8 }$* was stopped after 60 s (attempt $node_attempt of 3); at 55 s:" >&2
    cat "$node_diag" >&2
    echo "  its JavaScript stack (empty when its event loop did not answer):" >&2
    for report in "$node_reports"/*.json; do
      [ -f "$report" ] && grep -A15 '"javascriptStack"' "$report" >&2
    done
    [ $node_attempt -lt 3 ] || return $node_rc
    node_attempt=$((node_attempt + 1))
  done
}
