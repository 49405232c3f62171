#!/usr/bin/env bash
# tools/sweep-compare (docs/SLAM.md's tables of tried options): two sweeps of one short
# mission (drifting AHRS), the default and gathered keyframe clouds, give one row whose cell counts and means
# equal grid.csv's, worked out here with awk; a folder without its partner, or a directory
# without sweeps, is an error naming it.
# Usage: sweep_compare_test.sh ORTHOSONAR SOURCE_DIR WORK_DIR
set -euo pipefail
exe=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
printf 'slam:\n  keyframe_cloud_s: 30\n  keyframe_cloud_always: true\n' >gather.yaml
# The drifting AHRS: there scan matches weigh in the graph, so the two sweeps differ.
printf 'nav_profile: ahrs\n' >ahrs.yaml
for c in base gather; do
  cfg=()
  [ $c = base ] || cfg=(--config gather.yaml)
  "$exe" sweep --scene aircraft --duration 40 --resolution reduced --sim-config ahrs.yaml --no-report "${cfg[@]}" -o out/${c}_aircraft_s1 \
    >sweep_$c.txt 2>sweep_$c.err || fail "sweep ($c) exited $?: $(tail -5 sweep_$c.err)"
done
/usr/bin/python3 "$src/tools/sweep-compare" out base gather >table.md || fail "sweep-compare exited $?"
cat table.md
row=$(grep "^| aircraft (1) |" table.md) || fail "no aircraft row"
# The fusion cells of grid.csv: columns 1 system, 7 ate_dr_m, 8 ate_slam_m.
stats() {
  awk -F, 'NR > 1 && $1 == "fusion" { n++; if ($8 <= $7 + 1e-6) le++; ate += $8 }
           END { printf "%d %d %.4f", le, n, ate / n }' "out/$1_aircraft_s1/grid.csv"
}
read -r le_a n_a ate_a <<<"$(stats base)"
read -r le_b n_b ate_b <<<"$(stats gather)"
[ "$n_a" = "$n_b" ] && [ "$n_a" -gt 0 ] || fail "cells: $n_a and $n_b"
[ "$ate_a" != "$ate_b" ] || fail "the two sweeps gave the same mean SLAM ATE ($ate_a): the comparison shows nothing"
want_le="$le_a → $le_b of $n_a"
want_ate="$ate_a → $ate_b"
case $row in *"| $want_le |"*) ;; *) fail "SLAM ≤ DR: want '$want_le' in: $row" ;; esac
case $row in *"| $want_ate |"*) ;; *) fail "mean SLAM ATE: want '$want_ate' in: $row" ;; esac
mv out/gather_aircraft_s1 out/other_aircraft_s1
if /usr/bin/python3 "$src/tools/sweep-compare" out base gather >/dev/null 2>e.err; then fail "a missing partner passed"; fi
grep -q "gather_aircraft_s1 is missing" e.err || fail "missing partner message: $(cat e.err)"
mkdir empty
if /usr/bin/python3 "$src/tools/sweep-compare" empty base gather >/dev/null 2>e2.err; then fail "an empty directory passed"; fi
grep -q "no folder base_<scene>_s<seed>" e2.err || fail "empty directory message: $(cat e2.err)"
echo "sweep compare: ok"
