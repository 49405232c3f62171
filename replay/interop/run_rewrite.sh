#!/bin/sh
# ctest replay:interop-typescript-writer: the official TypeScript writer (@mcap/core
# McapWriter, npm) rewrites a short simulated fixture in each of its modes (rewrite.mjs:
# default, no summary and no indexes, no chunks, lz4, uncompressed, zstd chunks);
# `orthosonar replay` must give the original's digest for every rewrite, and `orthosonar
# inspect` must say how it read each. Then a rewrite cut short (a recorder that died) must
# replay with a warning. Exits 77 (ctest SKIP_RETURN_CODE) only when npm cannot install.
#   run_rewrite.sh <orthosonar> <source dir of the interop scripts> <npm dir> <work dir>
set -u
cli=$1
src=$2
npm_dir=$3
work=$4
. "$src/npm_setup.sh"
mkdir -p "$work" || exit 1
cd "$work" || exit 1
rm -f digests.txt
fail() { echo "interop-typescript-writer FAILED: $*"; exit 1; }

# A short reduced-resolution mission: every channel the pipeline reads, and the scene
# embedded as the attachments orthosonar_scene.yaml and orthosonar_scene.ply.
"$cli" simulate --scene marina1 --duration 10 --resolution reduced --threads 1 -q -o original.mcap \
  || fail "simulate"
reference=$("$cli" replay original.mcap -q -o out_original 2>replay_original.err) \
  || fail "replay of the original: $(cat replay_original.err)"
echo "original $reference" >digests.txt
# Every message of the original (the "nochunks" rewrite must hold them all outside chunks).
total=$("$cli" inspect original.mcap | sed -n 's/^duration: .*, \([0-9][0-9]*\) messages$/\1/p')
[ -n "$total" ] || fail "inspect original: no message count"

for mode in default nosummary nochunks lz4 uncompressed zstd; do
  echo "$(date +%T) rewrite $mode"
  node "$npm_dir/rewrite.mjs" original.mcap "$mode.mcap" "$mode" >"rewrite_$mode.json" || fail "rewrite $mode"
  digest=$(timeout 120 "$cli" replay "$mode.mcap" -q -o "out_$mode" 2>"replay_$mode.err") \
    || fail "replay of the $mode rewrite: $(cat "replay_$mode.err")"
  echo "$mode $digest" >>digests.txt
  [ "$digest" = "$reference" ] || fail "$mode rewrite: digest $digest, the original's $reference"
  ! grep -q "warning" "replay_$mode.err" || fail "$mode rewrite: replay warned: $(cat "replay_$mode.err")"
  "$cli" inspect "$mode.mcap" >"inspect_$mode.txt" 2>&1 || fail "inspect $mode: exit $?: $(cat "inspect_$mode.txt")"
  "$cli" inspect "$mode.mcap" --json >"inspect_$mode.json" 2>/dev/null || fail "inspect --json $mode"
  grep -q "orthosonar_scene.ply (application/x-ply" "inspect_$mode.txt" || fail "$mode rewrite lost the scene attachment"
  case $mode in
    nosummary) want_summary="summary: missing, read by linear scan"; want_json='"read_by_linear_scan": true' ;;
    *) want_summary="summary: present;"; want_json='"read_by_linear_scan": false' ;;
  esac
  case $mode in
    nochunks) want_compression="compression: none (no chunks); $total messages outside chunks" ;;
    lz4) want_compression="compression: lz4" ;;
    zstd) want_compression="compression: zstd" ;;
    *) want_compression="compression: none" ;;
  esac
  grep -q "^$want_summary" "inspect_$mode.txt" || fail "inspect $mode: no '$want_summary': $(head -3 "inspect_$mode.txt")"
  grep -q "$want_compression" "inspect_$mode.txt" || fail "inspect $mode: no '$want_compression'"
  grep -q "$want_json" "inspect_$mode.json" || fail "inspect --json $mode: no '$want_json'"
done

# A recorder that died: the no-summary rewrite (Schema and Channel records inside its
# chunks) and the lz4 one, cut at two thirds. Replay exits 1 and warns; with
# --allow-incomplete it maps what is left, still warning.
for mode in nosummary lz4; do
  size=$(wc -c <"$mode.mcap")
  head -c $((size * 2 / 3)) "$mode.mcap" >"died_$mode.mcap"
  timeout 120 "$cli" replay "died_$mode.mcap" -q -o "out_died_strict_$mode" >/dev/null 2>&1; rc=$?
  [ $rc -eq 1 ] || fail "replay of the cut $mode rewrite without --allow-incomplete: exit $rc, expected 1"
  digest=$(timeout 120 "$cli" replay "died_$mode.mcap" -q --allow-incomplete -o "out_died_$mode" 2>"replay_died_$mode.err") \
    || fail "replay --allow-incomplete of the cut $mode rewrite: $(cat "replay_died_$mode.err")"
  grep -q "warning: .*died_$mode.mcap: input cut at byte offset" "replay_died_$mode.err" \
    || fail "cut $mode rewrite: no truncation warning: $(cat "replay_died_$mode.err")"
  "$cli" inspect "died_$mode.mcap" >"inspect_died_$mode.txt" 2>&1; rc=$?
  [ $rc -eq 1 ] || fail "inspect of the cut $mode rewrite: exit $rc, expected 1"
  grep -q "^summary: missing, read by linear scan" "inspect_died_$mode.txt" || fail "cut $mode rewrite: summary line"
  grep -q "recovery: INCOMPLETE" "inspect_died_$mode.txt" || fail "cut $mode rewrite: recovery line"
  echo "died_$mode $digest (incomplete, as expected)" >>digests.txt
done
cat digests.txt
echo "interop-typescript-writer ok: 6 rewrites by @mcap/core McapWriter replay to the original's digest"
