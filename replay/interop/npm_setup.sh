# Sourced by the TypeScript interop tests (run_interop.sh, run_rewrite.sh, and the ros/,
# run/ interop scripts): npm-installs package.json (the official TypeScript MCAP libraries
# and Foxglove's ROS serialisers) into the build tree, once per version of package.json,
# and copies the scripts beside node_modules (node resolves imports from a script's folder).
# Needs $src (this folder) and $npm_dir; exits 77 (ctest SKIP_RETURN_CODE) only when npm
# cannot install the packages. Nothing may hang: npm gets 240 s (a registry that drops
# packets would otherwise hold it for 15 minutes), a failed install is remembered so the
# other interop tests skip at once, and every `node` call of the sourcing script is
# stopped after 300 s with a message saying which.
mkdir -p "$npm_dir" || exit 1
cp "$src/package.json" "$src"/*.mjs "$npm_dir/" || exit 1
stamp="$npm_dir/node_modules/.orthosonar-installed"
unavailable="$npm_dir/.orthosonar-npm-unavailable"
if [ ! -f "$stamp" ] || ! cmp -s "$npm_dir/package.json" "$stamp"; then
  if ! command -v npm >/dev/null 2>&1 || ! command -v node >/dev/null 2>&1; then
    echo "SKIP: npm or node is not installed; cannot fetch the TypeScript MCAP libraries"
    exit 77
  fi
  if [ -f "$unavailable" ] && cmp -s "$npm_dir/package.json" "$unavailable"; then
    echo "SKIP: npm could not install the packages earlier in this build (see $npm_dir/npm-install.log)"
    exit 77
  fi
  if ! (cd "$npm_dir" && timeout 240 npm install --no-audit --no-fund --no-package-lock --fetch-timeout=60000 \
          --fetch-retries=1 >npm-install.log 2>&1); then
    cp "$npm_dir/package.json" "$unavailable"
    echo "SKIP: npm cannot install the packages within 240 s (see $npm_dir/npm-install.log)"
    tail -5 "$npm_dir/npm-install.log"
    exit 77
  fi
  rm -f "$unavailable"
  cp "$npm_dir/package.json" "$stamp"
fi
node() {
  timeout 300 node "$@"
  node_rc=$?
  [ $node_rc -ne 124 ] || echo "node $* was stopped after 300 s" >&2
  return $node_rc
}
