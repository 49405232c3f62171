#!/bin/sh
# ctest replay:interop-typescript-mcap: npm-installs the official MCAP reader into the build
# tree (cached), writes a fixture with every channel, and reads it with check.mjs.
# Exits 77 (ctest SKIP_RETURN_CODE) only when npm cannot install the packages.
#   run_interop.sh <orthosonar_interop_fixture> <source dir of check.mjs> <work dir>
set -u
writer=$1
src=$2
work=$3
npm_dir=$work
. "$src/npm_setup.sh"
cd "$work" || exit 1
"$writer" fixture.mcap >expected.json || exit 1
node check.mjs fixture.mcap expected.json
