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
# stopped after 120 s with its JavaScript stack printed, and run once more (see node()).
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
node() {
  # Every script these tests run finishes in a few seconds. A node that has not finished
  # in 120 s is stuck outside our code (seen once in CI: the zstd rewrite, fine on every
  # rerun); it is asked for a diagnostic report (its JavaScript stack, printed here so the
  # next occurrence says where), stopped, and run once more. A script that fails, or
  # sticks twice, still fails the test.
  node_attempt=1
  while :; do
    node_reports=$(mktemp -d "$npm_dir/node-report.XXXXXX") || return 1
    timeout -s USR2 -k 10 120 node --report-on-signal --report-signal=SIGUSR2 \
      --report-directory="$node_reports" "$@"
    node_rc=$?
    if [ $node_rc -ne 124 ] && [ $node_rc -ne 137 ]; then
      rm -rf "$node_reports"
      return $node_rc
    fi
    echo "node $* was stopped after 120 s (attempt $node_attempt); its JavaScript stack:" >&2
    for report in "$node_reports"/*.json; do
      [ -f "$report" ] && grep -A15 '"javascriptStack"' "$report" >&2
    done
    [ $node_attempt -lt 2 ] || return $node_rc
    node_attempt=$((node_attempt + 1))
  done
}
