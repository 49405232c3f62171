#!/usr/bin/env bash
# `orthosonar perception-check` per image profile, beside a real Oculus ping (docs/PERCEPTION.md):
#  1. both profiles (field, clean) and the real M1200d ping are in the JSON; the ping has 256
#     beams and mean intensity 55.86 (testdata/oculus/README.md); the clean profile's water
#     p99 is below the field's on the vertical sonar and its h water p50 above the field's; the
#     association bound is at most the fused MAE; the JSON is the same bytes on a second run;
#  2. --fixture on a labelled fixture measures it as recorded (its profile, embedded scene);
#     --cloud writes its true-pose fused points: as many as the JSON counts, their mean
#     distance_m the JSON's MAE; an unwritable --cloud path exits 2 naming it;
#  3. a fixture without labels, a bad --real-ping path, a bad --profile and an unknown scene
#     exit 2 with a message naming the culprit.
# Usage: perception_check_test.sh ORTHOSONAR SOURCE_DIR WORK_DIR
set -euo pipefail
exe=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
ping=$src/testdata/oculus/m1200d_one_ping_8bit.raw
short=(--scene harbor --resolution reduced --duration 6 --every 2)

# jsonq FILE EXPR: a Python expression over `d` (the parsed JSON), printed as JSON unless a
# string. Debian's own python3, so every check runs on every machine (no optional jq).
jsonq() {
  /usr/bin/python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); v=eval(sys.argv[2]); print(json.dumps(v) if not isinstance(v,str) else v)' "$1" "$2"
}

echo "== 1. both profiles and a real ping"
"$exe" perception-check "${short[@]}" --profile both --real-ping "$ping" --json a.json >a.txt 2>a.err ||
  fail "perception-check exited $?: $(cat a.err)"
grep -q "^== profile field" a.txt || fail "no field section: $(cat a.txt)"
grep -q "^== profile clean" a.txt || fail "no clean section"
grep -q "label-free" a.txt || fail "no label-free section"
grep -q "real m1200d_one_ping_8bit.raw" a.txt || fail "real ping row missing"
test "$(jsonq a.json '",".join(p["label"] for p in d["profiles"])')" = "field,clean" ||
  fail "profiles: $(jsonq a.json '[p["label"] for p in d["profiles"]]')"
test "$(jsonq a.json 'len(d["real_pings"])')" = 1 || fail "real pings missing"
test "$(jsonq a.json 'd["real_pings"][0]["beams"]')" = 256 || fail "beams $(jsonq a.json 'd["real_pings"][0]["beams"]')"
test "$(jsonq a.json '55.85 < d["real_pings"][0]["label_free"]["all"]["mean"] < 55.87')" = true ||
  fail "real ping mean $(jsonq a.json 'd["real_pings"][0]["label_free"]["all"]["mean"]'), expected 55.86"
# The field profile's TVG lifts the 1.2 MHz vertical sonar's far-field noise above the
# clean profile's range-independent floor, while its near field is darker.
prof() { echo "[p for p in d['profiles'] if p['label']=='$1'][0]"; }
test "$(jsonq a.json "$(prof field)['mounts']['h']['label_based']['water']['p50'] < $(prof clean)['mounts']['h']['label_based']['water']['p50']")" = true ||
  fail "h: field water p50 not below clean's"
for m in v; do
  test "$(jsonq a.json "$(prof clean)['mounts']['$m']['label_based']['water']['p99'] < $(prof field)['mounts']['$m']['label_based']['water']['p99']")" = true ||
    fail "$m: clean water p99 not below field's: $(jsonq a.json "[p['mounts']['$m']['label_based']['water']['p99'] for p in d['profiles']]")"
done
test "$(jsonq a.json '"distance_to_mesh_m" in d["profiles"][0]["fusion"] and "within_0_1m" in d["profiles"][0]["fusion"]')" = true ||
  fail "fusion figures missing"
test "$(jsonq a.json '"precision_structure" in d["profiles"][0]["mounts"]["h"]["detections"]')" = true ||
  fail "structure precision missing"
# The association bound (issue 34): choosing among the bin's candidates or elevations can
# only lower a point's distance, so the bounds are at most the fused MAE, in that order.
# (The aircraft: the short harbor run above fuses no point.)
"$exe" perception-check --scene aircraft --resolution reduced --duration 6 --every 2 --profile field --json ab.json >ab.txt 2>ab.err ||
  fail "aircraft perception-check exited $?: $(cat ab.err)"
test "$(jsonq ab.json "(lambda f: f['points'] > 50 and f['association_bound']['single_candidate_points'] <= f['points'] and f['association_bound']['mae_best_elevation_in_overlap'] <= f['association_bound']['mae_best_candidate_of_bin'] <= f['association_bound']['mae_fused'] == f['distance_to_mesh_m']['mae'])(d['profiles'][0]['fusion'])")" = true ||
  fail "association bound: $(jsonq ab.json "d['profiles'][0]['fusion']['association_bound']"), points $(jsonq ab.json "d['profiles'][0]['fusion']['points']")"
grep -q "association bound: MAE as fused" ab.txt || fail "no association bound line: $(cat ab.txt)"
"$exe" perception-check "${short[@]}" --real-ping "$ping" --json b.json >/dev/null 2>&1 || fail "second run failed"
cmp -s a.json b.json || fail "JSON differs between two identical runs"

echo "== 2. --fixture on a labelled fixture"
"$exe" simulate --scene harbor --profile field --labels --resolution reduced --duration 6 -q -o labelled.mcap || fail "simulate --labels failed"
"$exe" perception-check --fixture labelled.mcap --every 2 --json f.json >f.txt 2>f.err ||
  fail "--fixture exited $?: $(cat f.err)"
grep -q "^== fixture labelled.mcap (profile field, as recorded)" f.txt || fail "fixture heading: $(head -3 f.txt)"
test "$(jsonq f.json 'len(d["profiles"])')" = 1 || fail "fixture: expected one result"
test "$(jsonq f.json 'd["profiles"][0]["profile"]')" = field || fail "fixture profile"
# Same images as the simulated field run: the same label-based figures.
test "$(jsonq f.json 'd["profiles"][0]["mounts"]')" = "$(jsonq a.json 'd["profiles"][0]["mounts"]')" ||
  fail "fixture figures differ from the simulated field profile's"
# The breakwater example: its first seconds see the sloped arm (the harbor's see nothing to fuse).
"$exe" simulate --scene-file "$src/docs/examples/breakwater/breakwater.yaml" --labels --resolution reduced \
  --duration 10 -q -o bw.mcap || fail "simulate breakwater failed"
"$exe" perception-check --fixture bw.mcap --every 2 --json c.json --cloud c.ply >c.txt 2>c.err ||
  fail "--cloud exited $?: $(cat c.err)"
grep -q "with their mesh distance -> c.ply" c.txt || fail "--cloud line: $(tail -3 c.txt)"
/usr/bin/python3 - c.ply c.json <<'PY' || fail "--cloud file does not match the JSON figures"
import json, struct, sys
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
head = data[:end].decode().splitlines()
assert head[1] == "format binary_little_endian 1.0", head[1]
n = int(next(l for l in head if l.startswith("element vertex")).split()[2])
props = [l.split()[2] for l in head if l.startswith("property float")]
assert props[:4] == ["x", "y", "z", "distance_m"], props
rows = list(struct.iter_unpack("<%df" % len(props), data[end:]))
fusion = json.load(open(sys.argv[2]))["profiles"][0]["fusion"]
assert n == len(rows) == fusion["points"] > 0, (n, len(rows), fusion["points"])
mae = sum(r[3] for r in rows) / n
assert abs(mae - fusion["distance_to_mesh_m"]["mae"]) < 1e-4, (mae, fusion["distance_to_mesh_m"]["mae"])
PY
set +e
"$exe" perception-check --fixture bw.mcap --every 2 --cloud no/such/dir/c.ply >/dev/null 2>c2.err; rc=$?
set -e
test $rc = 2 || fail "unwritable --cloud: exit $rc, expected 2"
grep -q "no/such/dir/c.ply" c2.err || fail "unwritable --cloud message: $(cat c2.err)"

echo "== 3. errors exit 2 naming the culprit"
"$exe" simulate --scene harbor --resolution reduced --duration 6 -q -o unlabelled.mcap || fail "simulate failed"
set +e
"$exe" perception-check --fixture unlabelled.mcap >/dev/null 2>e1.err; rc=$?
test $rc = 2 || fail "unlabelled fixture: exit $rc, expected 2"
grep -q "unlabelled.mcap" e1.err && grep -qi "label" e1.err || fail "unlabelled fixture message: $(cat e1.err)"
"$exe" perception-check "${short[@]}" --real-ping no/such/ping.raw >/dev/null 2>e2.err; rc=$?
test $rc = 2 || fail "bad --real-ping: exit $rc, expected 2"
grep -q "no/such/ping.raw" e2.err || fail "bad --real-ping message: $(cat e2.err)"
head -c 1000 "$ping" >cut.raw
"$exe" perception-check "${short[@]}" --real-ping cut.raw >/dev/null 2>e3.err; rc=$?
test $rc = 2 || fail "truncated --real-ping: exit $rc, expected 2"
grep -q "cut.raw" e3.err || fail "truncated --real-ping message: $(cat e3.err)"
"$exe" perception-check "${short[@]}" --profile murky >/dev/null 2>e4.err; rc=$?
test $rc = 2 || fail "bad --profile: exit $rc, expected 2"
grep -q "murky" e4.err || fail "bad --profile message: $(cat e4.err)"
"$exe" perception-check --scene atlantis --resolution reduced --duration 6 >/dev/null 2>e5.err; rc=$?
test $rc = 2 || fail "unknown scene: exit $rc, expected 2"
grep -q "atlantis" e5.err || fail "unknown scene message: $(cat e5.err)"
set -e
echo "ok"
