#!/usr/bin/python3
"""Writes Rowe Technologies (RTI) binary ensembles independently of orthosonar's C++ encoder,
with Python's `struct` only (and `binascii.crc_hqx`, which Rowe's own rti_python RtbRowe.py
uses, to cross-check the hand-written CRC), for hal/drivers/rti_ensemble_test.cpp.

The layout, as Rowe's libraries read and write it (rowetechinc/rti_python Codecs/BinaryCodec.py,
Ensemble/Ensemble.py, Ensemble/EnsembleData.py, Ensemble/BottomTrack.py, Codecs/RtbRowe.py;
rowetechinc/RTI Codec/AdcpBinaryCodec.cs, DataSet/Ensemble.cs), little-endian throughout:
  header   16 x 0x80, ensemble number (int32), its complement, payload size (int32), its complement
  payload  data sets: value type (10 float, 20 int, 50 byte), elements, multiplier, image,
           name length, name ("E000010\\0"), elements x multiplier values (4 bytes, 1 for type 50)
  checksum CRC-16/XMODEM of the payload, as a uint32

Usage: write_ensembles.py OUTDIR  -> OUTDIR/python_stream.bin, OUTDIR/python_stream.expected
The stream: garbage, ensemble 1001 (ensemble data rev D, an amplitude profile skipped, 4-beam
bottom track), an NMEA line, ensemble 1002 (ensemble data of 13 values, ancillary and byte-typed
NMEA data sets skipped, 3-beam bottom track of the older 10-array layout with a bad X velocity),
ensemble 1003 with one payload byte flipped after its checksum, the first 100 bytes of 1004 then
1005 at once (1004 cut short), and the first 60 bytes of 1006 at the end.
"""
import binascii
import os
import struct
import sys

BAD = 88.888


def crc16_xmodem(data):
    """CRC-16/XMODEM bit by bit: poly 0x1021, init 0, no reflection, no final XOR."""
    crc = 0
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def data_set(name, value_type, elements, multiplier, values):
    head = struct.pack('<5i', value_type, elements, multiplier, 0, 8) + name.encode('ascii') + b'\0'
    return head + values


def floats(*v):
    return struct.pack('<%df' % len(v), *v)


def ensemble_data(number, rev_d):
    ints = [number, 0, 4, 1, 1, 0x0000, 2019, 3, 9, 12, 23, 24, 33]
    values = struct.pack('<13i', *ints)
    if rev_d:
        values += b'01300000000000000000000000000123'   # serial number, 32 characters
        values += bytes([5, 11, 2, ord('A')])          # firmware revision, minor, major, subsystem code
        values += bytes([0, 0, 0, 3])                  # subsystem configuration in the last byte
    return data_set('E000008', 20, 23 if rev_d else 13, 1, values)


def bottom_track(beams, instrument, ranges, earth, status, pulse_coherent):
    scalars = [12.5, 12.75, 152.25, 1.5, -2.25, 15.25, 20.5, 35.0, 23.5, 1.25, 1500.0, float(status),
               float(beams), 23.0]
    per_beam = [ranges, [30.0 + b for b in range(beams)], [60.0 + b for b in range(beams)],
                [0.5] * beams, [BAD] * beams, [0.0] * beams, instrument, [1.0] * beams, earth, [1.0] * beams]
    values = floats(*scalars)
    for a in per_beam:
        values += floats(*a)
    groups = 15 if pulse_coherent else 10
    if pulse_coherent:
        values += floats(*([0.0] * (5 * beams)))
    return data_set('E000010', 10, 14 + groups * beams, 1, values)


def ensemble(number, sets):
    payload = b''.join(sets)
    crc = crc16_xmodem(payload)
    assert crc == binascii.crc_hqx(payload, 0), 'hand-written CRC disagrees with binascii.crc_hqx'
    head = b'\x80' * 16 + struct.pack('<4I', number, number ^ 0xFFFFFFFF, len(payload), len(payload) ^ 0xFFFFFFFF)
    return head + payload + struct.pack('<I', crc)


def main(outdir):
    e1001 = ensemble(1001, [
        ensemble_data(1001, True),
        data_set('E000004', 10, 30, 4, floats(*[float(i % 97) for i in range(120)])),   # amplitude profile
        bottom_track(4, [0.5, -0.25, 0.125, 0.0078125], [10.0, 10.5, 11.0, 11.5], [1.0, 2.0, 3.0, 0.0], 0x0002, True),
    ])
    nmea = b'$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n'
    e1002 = ensemble(1002, [
        ensemble_data(1002, False),
        data_set('E000009', 10, 19, 1, floats(*[float(i) for i in range(19)])),   # ancillary
        data_set('E000011', 50, 45, 1, (b'$HEHDT,274.07,T*03\r\n' + b'\0' * 45)[:45]),  # NMEA, byte type
        bottom_track(3, [BAD, 0.75, -0.5], [5.0, 0.0, 6.0], [BAD, BAD, BAD], 0x0008, False),
    ])
    e1003 = bytearray(ensemble(1003, [bottom_track(4, [0.25, 0.25, 0.0, 0.0], [3.0] * 4, [0.0] * 4, 0, True)]))
    e1003[40] ^= 0x01   # a payload byte corrupted after the checksum was computed
    e1004 = ensemble(1004, [ensemble_data(1004, True), bottom_track(4, [0.0] * 4, [2.0] * 4, [0.0] * 4, 0, True)])
    e1005 = ensemble(1005, [bottom_track(4, [-1.5, 0.0625, 0.03125, 0.0], [7.0, 7.0, 8.0, 8.0], [0.0] * 4, 0, True)])
    e1006 = ensemble(1006, [ensemble_data(1006, True)])

    garbage = b'garbage'
    parts = [garbage, e1001, nmea, e1002, bytes(e1003), e1004[:100], e1005, e1006[:60]]
    stream = b''.join(parts)
    offsets = {}
    at = 0
    for name, p in zip(['garbage', 1001, 'nmea', 1002, 1003, 1004, 1005, 1006], parts):
        offsets[name] = at
        at += len(p)
    skipped = len(garbage) + len(nmea) + len(e1003) + 100
    expected = [
        'ensembles=3', 'bad_checksum=1', 'partial=2', 'malformed=0', 'unknown_data_sets=3',
        'skipped_bytes=%d' % skipped, 'trailing_bytes=60',
        'offset.1001=%d' % offsets[1001], 'size.1001=%d' % len(e1001),
        'offset.1002=%d' % offsets[1002], 'size.1002=%d' % len(e1002),
        'offset.1005=%d' % offsets[1005], 'size.1005=%d' % len(e1005),
        'crc.1001=%d' % struct.unpack('<I', e1001[-4:])[0],
        'crc.123456789=%d' % crc16_xmodem(b'123456789'),
    ]
    with open(os.path.join(outdir, 'python_stream.bin'), 'wb') as f:
        f.write(stream)
    with open(os.path.join(outdir, 'python_stream.expected'), 'w') as f:
        f.write('\n'.join(expected) + '\n')


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit('usage: write_ensembles.py OUTDIR')
    main(sys.argv[1])
