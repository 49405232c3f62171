#!/bin/sh
# The sweep computes inference_submap's per-pair clouds once and replays them in every cell
# (replay/run/sweep.cpp). The reference cell (3 m / 30 deg) must equal a plain replay with
# the same model: same coverage, MAE and RMSE to the printed precision.
# Usage: sweep_inference_cache_test.sh ORTHOSONAR OUT_DIR
set -e
cli=$1; out=$2
rm -rf "$out"; mkdir -p "$out"
"$cli" train-classifier --scenes marina1,marina2 --duration 60 --resolution full --stride 4 --epochs 3 --per-class 60 \
  -o "$out/model.pt" > "$out/train.log"
"$cli" simulate --scene aircraft --duration 45 --resolution reduced -q -o "$out/m.mcap"
"$cli" sweep --scene aircraft --fixture "$out/m.mcap" --no-report --systems submap,inference_submap \
  --model "$out/model.pt" -o "$out/sweep" > /dev/null 2>&1
"$cli" replay "$out/m.mcap" -q --systems submap,inference_submap --model "$out/model.pt" -o "$out/replay" \
  > /dev/null 2>&1
cell=$(grep '^inference_submap,3,30,' "$out/sweep/grid.csv" | cut -d, -f4-6)
cov=$(grep -o '"coverage_voxels": [0-9]*' "$out/replay/inference_submap/metrics.json" | grep -o '[0-9]*$')
mae=$(grep -o '"mae_m": [-0-9.e]*' "$out/replay/inference_submap/metrics.json" | grep -o '[-0-9.e]*$')
rmse=$(grep -o '"rmse_m": [-0-9.e]*' "$out/replay/inference_submap/metrics.json" | grep -o '[-0-9.e]*$')
direct=$(printf '%s,%.6f,%.6f' "$cov" "$mae" "$rmse")
echo "sweep cell (cached inference): $cell"
echo "plain replay:                  $direct"
test -n "$cell"
test "$cov" -gt 0
test "$cell" = "$direct"
