#!/bin/sh
# ctest drivers:dsp1760-capture: the KVH DSP-1760 capture in testdata/dsp1760/ is what an
# independent writer (Python's struct and a hand CRC-32/MPEG-2, checked against the CRC
# catalogue, python3-crcmod when installed and a real KVH packet) builds, and `orthosonar
# inspect --protocol dsp1760` decodes it: every packet with its offset and fields, the counts.
#   dsp1760_capture_test.sh ORTHOSONAR SOURCE_DIR OUT_DIR
set -eu
cli=$1
src=$2
out=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
capture=$src/testdata/dsp1760/python_struct.bin

/usr/bin/python3 "$src/testdata/dsp1760/make_capture.py" --check "$capture" || fail "the capture is not what Python builds"
/usr/bin/python3 "$src/testdata/dsp1760/make_capture.py" "$out/rebuilt.bin"
cmp "$out/rebuilt.bin" "$capture" || fail "rebuilt capture differs"

# One bad CRC: exit 1, as for any protocol with a rejected message.
set +e
"$cli" inspect --protocol dsp1760 "$capture" > "$out/inspect.txt"
rc=$?
set -e
[ $rc -eq 1 ] || fail "inspect exit $rc, want 1 (one bad CRC)"
[ "$(grep -c '^@[0-9]* packet X=' "$out/inspect.txt")" -eq 4 ] || fail "not 4 packet lines: $(cat "$out/inspect.txt")"
grep -q '^@8 packet X=0.000122070312 Y=-0.000244140625 Z=6.10351562e-05 status=0x07 valid_x=true valid_y=true valid_z=true sequence=126 temperature_raw=2500 crc=0x' \
  "$out/inspect.txt" || fail "first packet line: $(grep -m1 '^@' "$out/inspect.txt")"
grep -q '^@44 packet .* valid_z=false sequence=127 ' "$out/inspect.txt" || fail "second packet"
grep -q '^@152 packet .* sequence=3 .* missing_before=2$' "$out/inspect.txt" || fail "the gap before sequence 3"
grep -q '(dsp1760): 4 good, 1 bad, 0 unsupported, 0 duplicate, 0 other message(s); 44 skipped byte(s), 20 trailing byte(s); 1 sequence gap(s), 2 missing packet(s)' \
  "$out/inspect.txt" || fail "counts: $(grep 'good,' "$out/inspect.txt")"
grep -q '^last error: dsp1760: byte 116: CRC mismatch: bytes 32-35 say 0x' "$out/inspect.txt" || fail "last error: $(tail -1 "$out/inspect.txt")"

set +e
"$cli" inspect --protocol dsp1760 "$capture" --json --csv "$out/dsp1760.csv" > "$out/inspect.json"
set -e
/usr/bin/python3 - "$out/inspect.json" "$out/dsp1760.csv" <<'PY' || fail "json/csv"
import csv, json, sys
doc = json.load(open(sys.argv[1]))
c = doc["counts"]
assert (c["good"], c["bad"], c["sequence_gaps"], c["missing_packets"], c["trailing_bytes"]) == (4, 1, 1, 2, 20), c
assert [m["offset"] for m in doc["messages"]] == [8, 44, 80, 152]
assert doc["messages"][2]["fields"]["temperature_raw"] == -1050
rows = list(csv.DictReader(open(sys.argv[2])))
assert len(rows) == 4 and rows[1]["Y"] == "1.5" and rows[3]["missing_before"] == "2", rows
PY

# The other protocols' parsers do not take DSP-1760 bytes for theirs.
set +e
"$cli" inspect --protocol vn100 "$capture" > /dev/null 2> "$out/wrong.err"; rc=$?
set -e
[ $rc -eq 2 ] || fail "vn100 on a DSP-1760 capture: exit $rc, want 2"
echo "dsp1760 capture: ok"
