#!/usr/bin/python3
"""A KVH DSP-1760 capture written independently of the C++ driver: Python's struct for the
36-byte layout and a bit-by-bit CRC-32/MPEG-2 written here (docs/DRIVERS.md "KVH DSP-1760").

  make_capture.py OUT            write the capture
  make_capture.py --check FILE   rebuild it in memory and compare with FILE (exit 1 if different)

Before writing, the CRC is checked three ways: the CRC catalogue's check value of
"123456789" (0x0376E6E7), python3-crcmod's predefined 'crc-32-mpeg' when it is installed,
and a real packet of a KVH 1750 IMU (same "Format A" message: header FE 81 FF 55, CRC over
bytes 0-31, big-endian), published as test data by a public KVH 1750 decoder. zlib.crc32
(the reflected CRC-32 of zip/Ethernet) must NOT verify that packet.

The capture (208 bytes; hal/drivers/dsp1760_test.cpp and dsp1760_capture_test.sh expect it):
  @0    8 bytes of garbage, among them a false header prefix FE 81 FF
  @8    seq 126, status 0x07, 25.00 C
  @44   seq 127, status 0x03 (Z invalid), 25.12 C
  @80   seq 0 (the counter wraps: no gap), -10.5 C
  @116  seq 1 with its last CRC byte flipped: a bad CRC
  @152  seq 3: a gap of 2 packets (1, lost to the bad CRC, and 2)
  @188  the first 20 bytes of seq 4: truncated at the end of the capture
Temperatures in 1/100 degree C (=tempunits C_100); X Y Z are delta angles in rad.
"""
import struct
import sys
import zlib


def crc32_mpeg2(data):
    crc = 0xFFFFFFFF
    for byte in data:
        crc ^= byte << 24
        for _ in range(8):
            crc = ((crc << 1) ^ 0x04C11DB7) if crc & 0x80000000 else (crc << 1)
            crc &= 0xFFFFFFFF
    return crc


def packet(xyz, status, seq, temp_raw):
    body = struct.pack(">4sfff12sBBh", b"\xFE\x81\xFF\x55", *xyz, bytes(12), status, seq, temp_raw)
    assert len(body) == 32
    return body + struct.pack(">I", crc32_mpeg2(body))


# A KVH 1750 packet (gyro X Y Z, accel X Y Z, status 0x77, seq 61, 40 C, CRC 4B FA 34 D8).
KVH1750 = bytes.fromhex(
    "FE81FF55" "37A96A6E" "38586C1F" "B75BF862" "BF803E78" "BB650D28" "3B0A37AC" "77" "3D" "0028" "4BFA34D8")


def self_check():
    assert crc32_mpeg2(b"123456789") == 0x0376E6E7
    try:
        import crcmod.predefined
        other = crcmod.predefined.mkCrcFun("crc-32-mpeg")
        for data in (b"123456789", KVH1750[:32], packet((1.0, -2.0, 0.5), 7, 5, 2500)[:32]):
            assert other(data) == crc32_mpeg2(data)
    except ImportError:
        pass
    field = struct.unpack(">I", KVH1750[32:])[0]
    assert crc32_mpeg2(KVH1750[:32]) == field, "CRC-32/MPEG-2 does not verify the KVH 1750 packet"
    assert zlib.crc32(KVH1750[:32]) not in (field, struct.unpack("<I", KVH1750[32:])[0])


def capture():
    out = b"\x00\xFE\x81\xFFok\r\n"
    out += packet((2.0 ** -13, -(2.0 ** -12), 2.0 ** -14), 0x07, 126, 2500)
    out += packet((0.0, 1.5, -0.25), 0x03, 127, 2512)
    out += packet((-(2.0 ** -10), 0.0, 2.0 ** -20), 0x07, 0, -1050)
    bad = bytearray(packet((0.125, 0.125, 0.125), 0x07, 1, 2500))
    bad[35] ^= 0xFF
    out += bytes(bad)
    out += packet((3.0e-4, -7.0e-5, 1.0e-6), 0x07, 3, 2499)
    out += packet((1.0, 1.0, 1.0), 0x07, 4, 2500)[:20]
    assert len(out) == 208
    return out


def main(argv):
    self_check()
    data = capture()
    if len(argv) == 3 and argv[1] == "--check":
        with open(argv[2], "rb") as f:
            if f.read() != data:
                print("make_capture.py: %s differs from the capture Python builds" % argv[2])
                return 1
        print("make_capture.py: %s equals the capture Python builds" % argv[2])
        return 0
    if len(argv) != 2:
        print(__doc__)
        return 2
    with open(argv[1], "wb") as f:
        f.write(data)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
