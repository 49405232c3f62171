#!/bin/sh
# ctest drivers:inspect-protocol: `orthosonar inspect --protocol` on raw captures, end to end.
#   inspect_protocol_test.sh ORTHOSONAR SOURCE_DIR OUT_DIR
set -eu
cli=$1
src=$2
out=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

# The real VN-100 log: 99 packets, no bad CRC, the ASCII between them skipped.
"$cli" inspect --protocol vn100 "$src/testdata/vn100/F00294" > "$out/vn100.txt" || fail "vn100 exit $?"
[ "$(grep -c '^@[0-9]* binary groups=0x14 ' "$out/vn100.txt")" -eq 99 ] || fail "vn100: not 99 packet lines"
grep -q '(vn100): 99 good, 0 bad, 0 unsupported, 0 duplicate, 0 other message(s); 2767 skipped byte(s), 0 trailing byte(s)' \
  "$out/vn100.txt" || fail "vn100 counts: $(tail -1 "$out/vn100.txt")"
# The first packet's attitude as the logger's author decoded it (F00294_B.csv, row 1, %.6e).
grep -m1 '^@64 ' "$out/vn100.txt" | grep -q ' Yaw=135.927414 Pitch=-7.07840729 Roll=14.2294369 ' || fail "vn100 first packet values"
head -2 "$src/testdata/vn100/F00294_B.csv" | tail -1 | grep -q ',1.359274e+02,-7.078407e+00,1.422944e+01,' || fail "author CSV changed"

# JSON and CSV of the same capture.
"$cli" inspect --protocol vn100 "$src/testdata/vn100/F00294" --json --csv "$out/vn100.csv" > "$out/vn100.json" || fail "vn100 --json"
/usr/bin/python3 - "$out/vn100.json" "$out/vn100.csv" <<'PY' || fail "vn100 json/csv"
import csv, json, sys
doc = json.load(open(sys.argv[1]))
c = doc["counts"]
assert (c["good"], c["bad"], c["unsupported"], c["skipped_bytes"]) == (99, 0, 0, 2767), c
assert len(doc["messages"]) == 99 and doc["messages"][0]["offset"] == 64
assert abs(doc["messages"][0]["fields"]["Yaw"] - 135.927414) < 1e-5
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 99 and rows[0]["offset"] == "64" and rows[0]["Roll"] == "14.2294369", rows[0]
PY

# The Oculus capture: one ping.
"$cli" inspect --protocol oculus "$src/testdata/oculus/m1200d_one_ping_8bit.raw" > "$out/oculus.txt" || fail "oculus exit"
grep -q '^@0 ping .* ping_id=415323 ' "$out/oculus.txt" || fail "oculus ping line"

# A50: json_v1 (no type), json_v3.1 twice (a duplicate), a response, a malformed line.
cat > "$out/a50.jsonl" <<'A50'
{"time": 170.5, "vx": -0.0056, "vy": -0.0076, "vz": -0.0076, "fom": 0.0019, "altitude": 0.61, "velocity_valid": true, "status": 0, "format": "json_v1"}
{"time": 106.4, "vx": 0.1, "vy": 0.2, "vz": 0.0, "fom": 0.001, "altitude": 0.49, "velocity_valid": true, "status": 0, "format": "json_v3.1", "type": "velocity", "time_of_validity": 1638191471563017, "time_of_transmission": 1638191471752336}
{"time": 106.4, "vx": 0.1, "vy": 0.2, "vz": 0.0, "fom": 0.001, "altitude": 0.49, "velocity_valid": true, "status": 0, "format": "json_v3.1", "type": "velocity", "time_of_validity": 1638191471563017, "time_of_transmission": 1638191471752336}
{"response_to":"get_config","success":true,"error_message":"","result":{},"format":"json_v3.1","type":"response"}
{"vx": 1
A50
set +e
"$cli" inspect --protocol a50 "$out/a50.jsonl" > "$out/a50.txt"
rc=$?
set -e
[ $rc -eq 1 ] || fail "a50 with a malformed line: exit $rc, want 1"
grep -q '(a50): 2 good, 1 bad, 0 unsupported, 1 duplicate, 1 other' "$out/a50.txt" || fail "a50 counts: $(cat "$out/a50.txt")"
grep -q '^last error: byte 748: dvl: A50 line is not a JSON object' "$out/a50.txt" || fail "a50 error offset: $(tail -1 "$out/a50.txt")"

# $PRTI and depth.
printf '$PRTI01,1000,8,1464,-1205,-24,-347,79380,300,-200,400,100,0000*21\r\n$GPGGA,x*00\r\n' > "$out/prti.txt"
"$cli" inspect --protocol prti "$out/prti.txt" > "$out/prti.out" || fail "prti exit"
grep -q '(prti): 1 good, 0 bad, 0 unsupported, 0 duplicate, 1 other' "$out/prti.out" || fail "prti counts"
printf '$DEPTH,3.25*7B\n{"type":"depth","depth":2.5}\n' > "$out/depth.txt"
"$cli" inspect --protocol depth "$out/depth.txt" > "$out/depth.out" || fail "depth exit"
grep -q '(depth): 2 good, 0 bad' "$out/depth.out" || fail "depth counts"

# Rowe RTI binary ensembles written by Python's struct (testdata/rti/write_ensembles.py): 3 good,
# a bad checksum and an ensemble cut short by the next (bad), the last cut by the end (trailing).
set +e
"$cli" inspect --protocol rti-ensemble "$src/testdata/rti/python_stream.bin" > "$out/rti.txt"; rc=$?
set -e
[ $rc -eq 1 ] || fail "rti-ensemble: exit $rc, want 1"
grep -q '(rti-ensemble): 3 good, 2 bad, 0 unsupported, 0 duplicate, 0 other message(s); 534 skipped byte(s), 60 trailing byte(s)' \
  "$out/rti.txt" || fail "rti-ensemble counts: $(tail -2 "$out/rti.txt")"
grep -q '^@7 ensemble ensemble_number=1001 .* bt_instrument_velocity_mps_x=0.5 bt_instrument_velocity_mps_y=-0.25 ' "$out/rti.txt" \
  || fail "rti-ensemble: ensemble 1001"
grep -q '^@2019 ensemble ensemble_number=1005 .* bottom_track_valid=true altitude_m=7.5$' "$out/rti.txt" || fail "rti-ensemble: ensemble 1005"

# Bad input: the wrong protocol for a file, an unknown protocol, a missing file: exit 2, named.
set +e
"$cli" inspect --protocol prti "$src/testdata/vn100/F00294" > /dev/null 2> "$out/wrong.err"; rc1=$?
"$cli" inspect --protocol nmea "$out/prti.txt" > /dev/null 2>&1; rc2=$?
"$cli" inspect --protocol vn100 "$out/missing.bin" > /dev/null 2> "$out/missing.err"; rc3=$?
set -e
[ $rc1 -eq 2 ] && grep -q "holds no prti message" "$out/wrong.err" || fail "wrong protocol: exit $rc1"
[ $rc2 -eq 2 ] || fail "unknown protocol: exit $rc2"
[ $rc3 -eq 2 ] && grep -q "missing.bin" "$out/missing.err" || fail "missing file: exit $rc3"
echo "inspect --protocol: ok"
