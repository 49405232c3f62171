#!/bin/sh
# ctest run:results-mcap-typescript: simulates a short reduced-resolution mission, replays it
# (`orthosonar replay -o DIR` writes DIR/results.mcap beside the other outputs) and reads
# results.mcap with the official TypeScript MCAP readers (replay/interop/results_check.mjs):
# every message decoded as Foxglove does and checked against the schema in the file.
# Exits 77 (ctest SKIP_RETURN_CODE) only when npm cannot install the packages.
#   interop_results.sh <orthosonar> <replay/interop source dir> <npm dir> <work dir>
set -u
orthosonar=$1
src=$2
npm_dir=$3
work=$4
. "$src/npm_setup.sh"
rm -rf "$work" && mkdir -p "$work" || exit 1
# The aircraft: the harbor's first seconds see nothing to map.
"$orthosonar" simulate --scene aircraft --duration 12 --resolution reduced --seed 3 --threads 1 -q \
  -o "$work/aircraft_12s.mcap" || exit 1
"$orthosonar" replay "$work/aircraft_12s.mcap" -o "$work/out" -q >"$work/digest.txt" || exit 1
if grep -q results "$work/out/digest.json"; then
  echo "results.mcap must not be a digest input"
  exit 1
fi
cd "$npm_dir" || exit 1
node results_check.mjs "$work/out/results.mcap" --maps-nonempty /orthosonar/fusion/map /orthosonar/submap/map \
  /orthosonar/trajectory/truth /orthosonar/trajectory/dr /orthosonar/trajectory/slam /orthosonar/tf /orthosonar/scene
