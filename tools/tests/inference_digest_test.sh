#!/bin/sh
# SPEC §9 for the inference systems: a replay with inference-based mapping and inference
# submapping gives one output digest over repeated runs and fusion thread counts (torch
# runs with fixed threads and seeds; MC-dropout seeds come from the ping ids).
# Usage: inference_digest_test.sh ORTHOSONAR OUT_DIR
set -e
cli=$1; out=$2
rm -rf "$out"; mkdir -p "$out"
"$cli" train-classifier --scenes marina1,marina2 --duration 40 --resolution full --stride 4 --epochs 6 --per-class 100 \
  -o "$out/model.pt" > "$out/train.log"
"$cli" simulate --scene marina1 --duration 30 --resolution full -q -o "$out/m.mcap"
digests=""
for run in 1-1 1-2 2-2 3-3; do
  t=${run#*-}
  d=$("$cli" replay "$out/m.mcap" -q --threads "$t" --systems fusion,inference,inference_submap \
        --model "$out/model.pt" -o "$out/replay_$run" 2>/dev/null | tail -n 1)
  echo "run $run (threads $t): $d"
  test -n "$d"
  digests="$digests $d"
done
# The inference systems must have done something, or the check proves nothing.
grep -q '"inference_inferred_points": [1-9]' "$out/replay_1-1/inference_submap/metrics.json"
test "$(echo $digests | tr ' ' '\n' | sort -u | wc -l)" -eq 1
