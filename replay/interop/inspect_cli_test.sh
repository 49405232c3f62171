#!/bin/sh
# ctest replay:inspect-cli: `orthosonar inspect` on a complete, a truncated and a non-MCAP
# file, checking output and exit codes (0 complete, 1 truncated, 2 bad input).
#   inspect_cli_test.sh <orthosonar> <orthosonar_interop_fixture> <work dir>
set -u
cli=$1
writer=$2
work=$3
mkdir -p "$work" || exit 1
cd "$work" || exit 1
fail() { echo "inspect-cli FAILED: $*"; exit 1; }
"$writer" full.mcap >expected.json || fail "cannot write the fixture"

"$cli" inspect full.mcap >text.out 2>&1; rc=$?
[ $rc -eq 0 ] || fail "complete file: exit $rc"
grep -q "/sonar/horizontal/ping *orthosonar_msgs/OculusPing *30 msgs" text.out || fail "text output: $(cat text.out)"
grep -q "recovery: complete file" text.out || fail "no recovery line"
grep -q "scene: interop" text.out || fail "no metadata"
grep -q "interop.txt (text/plain, 30 bytes)" text.out || fail "no attachment line: $(cat text.out)"

"$cli" inspect full.mcap --json >json.out 2>&1 || fail "--json exit $?"
grep -q '"messages": 375' json.out || fail "json messages: $(head -20 json.out)"
grep -q '"topic": "/imu/data"' json.out || fail "json channels"
grep -q '"name": "interop.txt"' json.out || fail "json attachments"

size=$(wc -c <full.mcap)
head -c $((size * 2 / 3)) full.mcap >cut.mcap
"$cli" inspect cut.mcap >cut.out 2>&1; rc=$?
[ $rc -eq 1 ] || fail "truncated file: exit $rc, expected 1: $(cat cut.out)"
grep -q "recovery: INCOMPLETE" cut.out || fail "truncated file: no recovery report"
grep -q "byte offset" cut.out || fail "truncated file: no byte offset"

printf 'MCAP? no, just text\n' >notmcap.bin
"$cli" inspect notmcap.bin >bad.out 2>&1; rc=$?
[ $rc -eq 2 ] || fail "non-MCAP file: exit $rc, expected 2: $(cat bad.out)"

# An MCAP file with a bad data section CRC: exit 2, the error names the file and offset.
python3 - <<'PY' || fail "python3"
b = bytearray(open("full.mcap", "rb").read())
b[len(b) // 3] ^= 0x20
open("crc.mcap", "wb").write(b)
PY
"$cli" inspect crc.mcap >crc.out 2>&1; rc=$?
[ $rc -eq 2 ] || fail "corrupt file: exit $rc, expected 2: $(cat crc.out)"
grep -q "crc.mcap: .* at byte offset" crc.out || fail "corrupt file message: $(cat crc.out)"
echo "inspect-cli ok"
