#!/usr/bin/env bash
# Keyframe heading against the truth (issue 33) through a sweep: every cell of grid.json has
# heading_rms_dr_deg / heading_rms_slam_deg (finite, >= 0), grid.csv has the columns,
# tables.md the per-cell line, and tools/sweep-heading-table prints the fixture's row (the
# 3 m / 30° cell's figures equal to grid.json's, rounded) and exits non-zero on a directory
# without sweeps.
# Usage: sweep_heading_test.sh ORTHOSONAR SOURCE_DIR WORK_DIR
set -euo pipefail
exe=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
"$exe" sweep --scene aircraft --duration 30 --resolution reduced --no-report -o out/aircraft >sweep.txt 2>sweep.err ||
  fail "sweep exited $?: $(tail -5 sweep.err)"
/usr/bin/python3 - <<'PY' || fail "grid.json heading fields"
import json, math
cells = json.load(open("out/aircraft/grid.json"))["cells"]
assert len(cells) == 30, len(cells)
for c in cells:
    for k in ("heading_rms_dr_deg", "heading_rms_slam_deg"):
        v = c[k]
        assert isinstance(v, float) and math.isfinite(v) and 0.0 <= v < 20.0, (k, v)
PY
head -1 out/aircraft/grid.csv | grep -q ",heading_rms_dr_deg,heading_rms_slam_deg$" || fail "grid.csv header: $(head -1 out/aircraft/grid.csv)"
grep -q "^Keyframe heading error per cell" out/aircraft/tables.md || fail "tables.md has no heading line"
"$src/tools/sweep-heading-table" out >table.md || fail "sweep-heading-table exited $?"
grep -q "^| aircraft |" table.md || fail "no aircraft row: $(cat table.md)"
want=$(/usr/bin/python3 -c 'import json; c=[c for c in json.load(open("out/aircraft/grid.json"))["cells"] if c["system"]=="fusion" and c["distance_m"]==3 and c["rotation_deg"]==30][0]; print("| aircraft | %.2f° | %.2f° |" % (c["heading_rms_dr_deg"], c["heading_rms_slam_deg"]))')
grep -qF "$want" table.md || fail "row '$want' not in: $(cat table.md)"
mkdir empty
if "$src/tools/sweep-heading-table" empty >/dev/null 2>e.err; then fail "an empty directory passed"; fi
grep -q "no grid.json" e.err || fail "empty directory message: $(cat e.err)"
echo "sweep heading: ok"
