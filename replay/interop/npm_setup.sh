# Sourced by run_interop.sh and run_rewrite.sh: npm-installs package.json (the official
# TypeScript MCAP libraries) into the build tree, once per version of package.json, and
# copies the scripts beside node_modules (node resolves imports from a script's folder).
# Needs $src (this folder) and $npm_dir; exits 77 (ctest SKIP_RETURN_CODE) only when npm
# cannot install the packages.
mkdir -p "$npm_dir" || exit 1
cp "$src/package.json" "$src"/*.mjs "$npm_dir/" || exit 1
stamp="$npm_dir/node_modules/.orthosonar-installed"
if [ ! -f "$stamp" ] || ! cmp -s "$npm_dir/package.json" "$stamp"; then
  if ! command -v npm >/dev/null 2>&1; then
    echo "SKIP: npm is not installed; cannot fetch @mcap/core, @mcap/support and lz4js"
    exit 77
  fi
  if ! (cd "$npm_dir" && npm install --no-audit --no-fund --no-package-lock >npm-install.log 2>&1); then
    echo "SKIP: npm cannot install @mcap/core, @mcap/support and lz4js (see $npm_dir/npm-install.log)"
    tail -5 "$npm_dir/npm-install.log"
    exit 77
  fi
  cp "$npm_dir/package.json" "$stamp"
fi
