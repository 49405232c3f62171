"""ctest ros:msg-genpy: our ROS 1 definitions and ros1 codec against genpy.

For every type orthosonar knows (orthosonar_msg_dump types):
  1. genpy.dynamic.generate_dynamic builds the classes from our ROS 1 text; their
     _md5sum must equal our MD5 (genmsg's rule, computed independently);
  2. genpy serialises random instances; our decoder must give the same field values;
  3. our Writer's sample message deserialises in genpy to the values our decoder reads,
     and genpy serialises it back to the same bytes.
Usage: msg_interop.py <orthosonar_msg_dump> <work dir>
"""
import io
import json
import os
import random
import struct
import subprocess
import sys

import genpy
import genpy.dynamic

DUMP, WORK = sys.argv[1], sys.argv[2]
RNG = random.Random(20240518)
INT_RANGES = {
    "int8": (-128, 127), "uint8": (0, 255), "byte": (-128, 127), "char": (0, 255),
    "int16": (-32768, 32767), "uint16": (0, 65535),
    "int32": (-2**31, 2**31 - 1), "uint32": (0, 2**32 - 1),
    "int64": (-2**63, 2**63 - 1), "uint64": (0, 2**64 - 1),
}
failures = []


def finite_from_bits(fmt, nbytes):
    while True:
        x = struct.unpack(fmt, RNG.getrandbits(8 * nbytes).to_bytes(nbytes, "little"))[0]
        if x == x and abs(x) != float("inf"):
            return x


def split_array(t):
    if t.endswith("]"):
        base, n = t[:-1].split("[")
        return base, (int(n) if n else None)
    return t, -1


def random_scalar(base, classes):
    if base in INT_RANGES:
        lo, hi = INT_RANGES[base]
        return RNG.randint(lo, hi)
    if base == "bool":
        return RNG.random() < 0.5
    if base == "float32":
        return finite_from_bits("<f", 4)
    if base == "float64":
        return finite_from_bits("<d", 8)
    if base == "string":
        return "".join(chr(RNG.randint(32, 126)) for _ in range(RNG.randint(0, 12)))
    if base == "time":
        return genpy.Time(RNG.randint(0, 2**32 - 1), RNG.randint(0, 999999999))
    if base == "duration":
        return genpy.Duration(RNG.randint(-2**31, 2**31 - 1), RNG.randint(0, 999999999))
    return random_message(classes[base], classes)


def random_message(cls, classes):
    msg = cls()
    for name, t in zip(cls.__slots__, cls._slot_types):
        base, n = split_array(t)
        if n == -1:
            setattr(msg, name, random_scalar(base, classes))
            continue
        count = n if n is not None else RNG.randint(0, 40 if base in ("uint8", "char") else 6)
        if base in ("uint8", "char"):
            setattr(msg, name, bytes(RNG.getrandbits(8) for _ in range(count)))
        else:
            setattr(msg, name, [random_scalar(base, classes) for _ in range(count)])
    return msg


def time_ns(v):
    if isinstance(v, dict):
        return v["sec"] * 10**9 + v["nsec"]
    return v.secs * 10**9 + v.nsecs


def compare(py, ours, t, classes, path, where):
    base, n = split_array(t)
    if n != -1:
        seq = list(py)
        if not isinstance(ours, list) or len(seq) != len(ours):
            where.append(f"{path}: length {len(seq)} vs {ours if not isinstance(ours, list) else len(ours)}")
            return
        for i, (a, b) in enumerate(zip(seq, ours)):
            compare(a, b, base, classes, f"{path}[{i}]", where)
        return
    if base in ("time", "duration"):
        if time_ns(py) != time_ns(ours):
            where.append(f"{path}: {time_ns(py)} vs {time_ns(ours)}")
    elif base == "bool":
        if int(bool(py)) != ours:
            where.append(f"{path}: {py} vs {ours}")
    elif base in INT_RANGES or base in ("float32", "float64", "string"):
        if py != ours:
            where.append(f"{path}: {py!r} vs {ours!r}")
    else:
        cls = classes[base]
        for name, ft in zip(cls.__slots__, cls._slot_types):
            if name not in ours:
                where.append(f"{path}.{name}: missing")
                continue
            compare(getattr(py, name), ours[name], ft, classes, f"{path}.{name}".lstrip("."), where)


def ours_decode(name, path):
    r = subprocess.run([DUMP, "decode", name, "ros1", path], capture_output=True, text=True)
    if r.returncode != 0:
        return None, r.stderr.strip()
    return json.loads(r.stdout), None


types = json.loads(subprocess.check_output([DUMP, "types"]))
checked = 0
for t in types:
    name = t["name"]
    classes = genpy.dynamic.generate_dynamic(name, t["ros1"])
    cls = classes[name]
    # 1. MD5
    if cls._md5sum != t["md5"]:
        failures.append(f"{name}: genpy md5 {cls._md5sum} vs ours {t['md5']}")
    # 2. genpy writes, we read
    for trial in range(12):
        msg = random_message(cls, classes)
        buf = io.BytesIO()
        msg.serialize(buf)
        path = os.path.join(WORK, f"{name.replace('/', '_')}_{trial}.ros1")
        with open(path, "wb") as f:
            f.write(buf.getvalue())
        ours, err = ours_decode(name, path)
        if err:
            failures.append(f"{name} trial {trial}: our decoder failed: {err}")
            continue
        where = []
        compare(msg, ours, name, classes, "", where)
        failures.extend(f"{name} trial {trial}: {w}" for w in where[:5])
        checked += 1
    # 3. we write, genpy reads
    path = os.path.join(WORK, f"{name.replace('/', '_')}_sample.ros1")
    subprocess.check_call([DUMP, "encode-sample", name, "ros1", path])
    data = open(path, "rb").read()
    try:
        msg = cls().deserialize(data)
    except Exception as e:  # genpy raises genpy.DeserializationError or struct.error
        failures.append(f"{name}: genpy cannot read our sample: {e}")
        continue
    buf = io.BytesIO()
    msg.serialize(buf)
    if buf.getvalue() != data:
        failures.append(f"{name}: genpy re-serialises our sample differently ({len(buf.getvalue())} vs {len(data)} bytes)")
    ours, err = ours_decode(name, path)
    if err:
        failures.append(f"{name}: our decoder fails on our sample: {err}")
        continue
    where = []
    compare(msg, ours, name, classes, "", where)
    failures.extend(f"{name} sample: {w}" for w in where[:5])
    checked += 1

for f in failures:
    print("FAIL:", f)
print(f"genpy interop: {len(types)} types, {checked} messages compared, {len(failures)} mismatches")
sys.exit(1 if failures else 0)
