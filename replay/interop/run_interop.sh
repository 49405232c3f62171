#!/bin/sh
# ctest replay:interop-typescript-mcap: npm-installs the official MCAP reader into the build
# tree (cached), writes a fixture with every channel, and reads it with check.mjs.
# Exits 77 (ctest SKIP_RETURN_CODE) only when npm cannot install the packages.
#   run_interop.sh <orthosonar_interop_fixture> <source dir of check.mjs> <work dir>
set -u
writer=$1
src=$2
work=$3
mkdir -p "$work" || exit 1
cp "$src/package.json" "$src/check.mjs" "$work/" || exit 1
cd "$work" || exit 1
stamp=node_modules/.orthosonar-installed
if [ ! -f "$stamp" ] || ! cmp -s package.json "$stamp"; then
  if ! command -v npm >/dev/null 2>&1; then
    echo "SKIP: npm is not installed; cannot fetch @mcap/core and @mcap/support"
    exit 77
  fi
  if ! npm install --no-audit --no-fund --no-package-lock >npm-install.log 2>&1; then
    echo "SKIP: npm cannot install @mcap/core and @mcap/support (see $work/npm-install.log)"
    tail -5 npm-install.log
    exit 77
  fi
  cp package.json "$stamp"
fi
"$writer" fixture.mcap >expected.json || exit 1
node check.mjs fixture.mcap expected.json
