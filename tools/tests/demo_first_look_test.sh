#!/bin/sh
# The README's first command as a user first sees it (issue 38): `orthosonar demo` maps whole
# structures and writes a report a reviewer can read without running anything.
#  - coverage: fusion >= 600 occupied 0.1 m voxels, submap >= 10000 (metrics.json);
#  - both maps have points on the sailing ship's hull (south side, x -63..-21, y -15..-4)
#    and on the pier (x -8..-2, y -31..0), read from map.ply;
#  - report.html is self-contained (only embedded images), at most 10 MB, with the new figures.
# Usage: demo_first_look_test.sh ORTHOSONAR OUT_DIR   (under xvfb-run -a, like all of ctest)
set -eu
cli=$1
out=$2
rm -rf "$out"
"$cli" demo -o "$out" > "$out.log" 2>&1 || { tail -20 "$out.log"; exit 1; }
py=/usr/bin/python3
"$py" - "$out" <<'PY'
import json, struct, sys
out = sys.argv[1]
def points(path):
    with open(path, 'rb') as f:
        header = b''
        while not header.endswith(b'end_header\n'):
            header += f.readline()
        n = int([l for l in header.split(b'\n') if l.startswith(b'element vertex')][0].split()[2])
        assert b'binary_little_endian' in header, path
        data = f.read(12 * n)
    return [struct.unpack_from('<3f', data, 12 * i) for i in range(n)]
regions = {'sailing ship hull': (-63, -21, -15, -4), 'pier': (-8, -2, -31, 0)}
need = {'fusion': (600, 30), 'submap': (10000, 300)}
bad = []
for system, (min_cov, min_pts) in need.items():
    cov = json.load(open(f'{out}/{system}/metrics.json'))['coverage_voxels']
    line = f'{system}: coverage {cov} (>= {min_cov})'
    if cov < min_cov: bad.append(line)
    pts = points(f'{out}/{system}/map.ply')
    for name, (x0, x1, y0, y1) in regions.items():
        k = sum(1 for x, y, z in pts if x0 <= x <= x1 and y0 <= y <= y1)
        line += f'; {name} {k} points (>= {min_pts})'
        if k < min_pts: bad.append(f'{system}: {name} {k} points')
    print(line)
if bad:
    print('FAIL: ' + '; '.join(bad)); sys.exit(1)
PY
html="$out/report/report.html"
size=$(wc -c < "$html")
echo "report.html: $size bytes"
[ "$size" -le 10485760 ] || { echo "FAIL: report.html over 10 MB"; exit 1; }
if grep -o -E '(src|href)="[^"]{0,11}' "$html" | grep -v 'data:image/'; then
  echo "FAIL: report.html references a file or URL"; exit 1
fi
for needle in "Where the map is wrong" "What the sonars saw" "trajectory_error.png" "error_fusion_top.png" "ping_pair.png"; do
  grep -q "$needle" "$html" || { echo "FAIL: report.html has no '$needle'"; exit 1; }
done
test -s "$out/ping_pair/ping_pair.json"
echo "ok"
