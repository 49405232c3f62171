#!/bin/sh
# golden:bounds-catch-a-violation (issue 35): `golden --check` must fail on a run outside its
# absolute bounds even when digest and metrics match the recorded expectations. The aircraft
# scenario is checked against a copy of golden/bounds.yaml with a coverage floor no map
# reaches and an expected-failure marker on a check that passes (SLAM beats dead reckoning
# there): exit 1, both named. The unchanged bounds pass.
# Usage: bounds_violation_test.sh ORTHOSONAR SOURCE_DIR WORK_DIR
set -u
exe=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
/usr/bin/python3 - "$src/golden/bounds.yaml" "$work/bounds_broken.yaml" <<'PY' || fail "cannot write the broken bounds"
import sys
s = open(sys.argv[1]).read()
a = s.index("  aircraft:")
s = s[:a] + s[a:].replace("    ate_slam_over_dr_max: 1.0\n", "    ate_slam_over_dr_max: 1.0\n    expected_failure:\n      slam_worse_than_dr: \"a marker on a check that passes\"\n", 1)
s = s.replace("coverage_min_voxels: 54}", "coverage_min_voxels: 1000000}", 1)
open(sys.argv[2], "w").write(s)
PY
"$exe" golden --check "$src/golden/scenarios/aircraft.yaml" --no-images -o "$work/out" \
  --bounds "$work/bounds_broken.yaml" >"$work/broken.txt" 2>&1
rc=$?
cat "$work/broken.txt"
[ $rc = 1 ] || fail "golden --check with violated bounds exited $rc, expected 1"
grep -q "^  digest\|digest differs" "$work/broken.txt" && fail "the digest should match: only the bounds are broken"
grep -q "bound FAIL fusion.coverage_voxels" "$work/broken.txt" || fail "the coverage floor violation is not named"
grep -q "UNEXPECTED PASS" "$work/broken.txt" || fail "the stale expected-failure marker is not named"
"$exe" golden --check "$src/golden/scenarios/aircraft.yaml" --no-images -o "$work/out" >"$work/ok.txt" 2>&1 ||
  fail "golden --check with the repository's bounds failed: $(cat "$work/ok.txt")"
echo "bounds violations caught"
