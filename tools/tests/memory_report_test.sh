#!/bin/sh
# replay --memory-report (issue 41): the CSV has a row per minute of sensor time and one per
# phase after the stream, every part as a column, resident memory read; the budget table is
# printed; the outputs and the digest are those of a replay without it; a path that cannot
# be written is an error naming it, exit 2.
set -eu
bin="$1"
out="$2"
rm -rf "$out"
mkdir -p "$out"
"$bin" simulate --scene harbor --duration 150 --resolution reduced --seed 3 -o "$out/m.mcap" -q
"$bin" replay "$out/m.mcap" -o "$out/plain" -q > "$out/plain.digest"
"$bin" replay "$out/m.mcap" -o "$out/mem" -q --memory-report "$out/memory.csv" > "$out/mem.digest" 2> "$out/mem.err"
cmp "$out/plain.digest" "$out/mem.digest" || { echo "the digest changed with --memory-report"; exit 1; }
head -n1 "$out/memory.csv" | grep -q '^sensor_s,phase,rss_mb,peak_rss_mb,decoder_buffers_mb,truth_mb,dead_reckoning_mb,ping_queue_mb,keyframe_clouds_mb,pose_graph_mb,map:fusion_mb,map:submap_mb,parts_mb$' \
  || { echo "unexpected header: $(head -n1 "$out/memory.csv")"; exit 1; }
# 150 s of sensor time: samples at 0, 60 and 120 s, then the three phases after the stream.
[ "$(grep -c ',stream,' "$out/memory.csv")" -eq 3 ] || { echo "expected 3 stream samples"; cat "$out/memory.csv"; exit 1; }
for phase in 'end of stream' metrics 'outputs written'; do
  grep -q ",$phase," "$out/memory.csv" || { echo "no '$phase' row"; exit 1; }
done
# Resident memory was read (tens of MB at least) and keyframe clouds are not empty at the end.
awk -F, 'NR > 1 && ($3 < 10 || $4 < $3) { bad = 1 } END { exit bad }' "$out/memory.csv" \
  || { echo "implausible resident memory"; cat "$out/memory.csv"; exit 1; }
awk -F, '$2 == "end of stream" && $9 > 0 { ok = 1 } END { exit !ok }' "$out/memory.csv" \
  || { echo "no keyframe clouds at the end of the stream"; cat "$out/memory.csv"; exit 1; }
grep -q '^| keyframe_clouds | ' "$out/mem.err" || { echo "no budget table"; cat "$out/mem.err"; exit 1; }
grep -q 'peak resident (VmHWM)' "$out/mem.err" || { echo "no peak line"; exit 1; }
# traj_truth.tum holds every truth pose (kept on disk during the run), the same file either way.
cmp "$out/plain/traj_truth.tum" "$out/mem/traj_truth.tum"
[ "$(wc -l < "$out/plain/traj_truth.tum")" -gt 10000 ] || { echo "traj_truth.tum is short"; exit 1; }
set +e
"$bin" replay "$out/m.mcap" -o "$out/bad" -q --memory-report "$out/no/such/dir/memory.csv" > /dev/null 2> "$out/bad.err"
rc=$?
set -e
[ "$rc" -eq 2 ] || { echo "unwritable --memory-report: exit $rc, expected 2"; exit 1; }
grep -q "no/such/dir/memory.csv" "$out/bad.err" || { echo "the error does not name the file"; cat "$out/bad.err"; exit 1; }
rm -f "$out/m.mcap"
echo "memory report ok"
