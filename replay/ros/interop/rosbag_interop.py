#!/usr/bin/python3
"""ctest ros:rosbag-python-interop: our rosbag reader and writer against Debian's
python3-rosbag, an independent implementation of the ROS 1 bag format 2.0.

  rosbag_interop.py <orthosonar_rosbag_dump> <work dir>

(a) python writes bags (none, bz2, lz4; several topics, sensor_msgs/Imu and a type with
    uint8[] and string fields, classes generated at run time by genpy) and our dump of each
    must match what it wrote: counts, topics, types, md5sums, times, message bytes;
(b) a python writer killed before close (os._exit) and a bag cut mid-chunk: our dump reads
    them by a scan and says so;
(c) our `copy` rewrites a python bag in each compression and python reads the copy back:
    read_messages, get_type_and_topic_info, deserialised messages equal to the originals.
Exits 1 with a message at the first mismatch.
"""
import hashlib
import io
import json
import os
import random
import subprocess
import sys

import genpy
import genpy.dynamic
import rosbag

SEP = "=" * 80 + "\n"
IMU_TEXT = (
    "std_msgs/Header header\n\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n\n"
    "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n\n"
    "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n\n"
    + SEP + "MSG: std_msgs/Header\nuint32 seq\ntime stamp\nstring frame_id\n\n"
    + SEP + "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w\n\n"
    + SEP + "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z\n")
BLOB_TEXT = "uint32 seq\nuint8[] data\nstring note\n"
Imu = genpy.dynamic.generate_dynamic("sensor_msgs/Imu", IMU_TEXT)["sensor_msgs/Imu"]
Blob = genpy.dynamic.generate_dynamic("orthosonar_test/Blob", BLOB_TEXT)["orthosonar_test/Blob"]
TOPICS = [("/imu/data", Imu), ("/blob/small", Blob), ("/blob/large", Blob)]

dump_tool, work = sys.argv[1], sys.argv[2]
os.makedirs(work, exist_ok=True)


def fail(what):
    print("rosbag interop FAILED: " + what)
    sys.exit(1)


def check(cond, what):
    if not cond:
        fail(what)


def make_messages(seed, n=90):
    """(topic, class, message, time) in write order; some large enough to fill chunks alone."""
    rnd = random.Random(seed)
    out = []
    for i in range(n):
        topic, cls = TOPICS[rnd.randrange(len(TOPICS))]
        t = genpy.Time(1700000000 + i // 10, rnd.randrange(1000000000))
        if cls is Imu:
            m = Imu()
            m.header.seq, m.header.stamp, m.header.frame_id = i, t, "imu_link"
            m.orientation.w = 1.0
            m.angular_velocity.z = rnd.uniform(-1, 1)
            m.linear_acceleration.z = 9.81 + rnd.uniform(-0.1, 0.1)
            m.orientation_covariance = [rnd.random() for _ in range(9)]
        else:
            size = rnd.choice([0, 1, 17, 300, 5000]) if topic == "/blob/small" else rnd.choice([20000, 100000])
            m = Blob(seq=i, data=rnd.randbytes(size), note="n\u00e9 %d =" % i)
        out.append((topic, cls, m, t))
    return out


def serialized(m):
    buf = io.BytesIO()
    m.serialize(buf)
    return buf.getvalue()


def time_ns(t):
    return t.secs * 1000000000 + t.nsecs


def write_python_bag(path, compression, msgs):
    with rosbag.Bag(path, "w", compression=compression, chunk_threshold=64 * 1024) as bag:
        for topic, _, m, t in msgs:
            bag.write(topic, m, t)


def dump(path, must_succeed=True):
    p = subprocess.run([dump_tool, "dump", path], capture_output=True, text=True)
    if p.returncode != 0:
        if must_succeed:
            fail("dump %s: exit %d: %s" % (path, p.returncode, p.stderr.strip()))
        return None
    return json.loads(p.stdout)


def expected_rows(msgs):
    return [(topic, time_ns(t), len(serialized(m)), hashlib.sha1(serialized(m)).hexdigest()) for topic, _, m, t in msgs]


def dumped_rows(d):
    return [(m["topic"], m["time_ns"], m["size"], m["sha1"]) for m in d["messages"]]


def check_prefix(d, msgs, label):
    got, want = dumped_rows(d), expected_rows(msgs)
    check(got == want[:len(got)], "%s: the messages read are not the first %d written" % (label, len(got)))
    return len(got)


def plain(v):
    """A message as nested python values, so messages of different generated classes compare."""
    if hasattr(v, "__slots__"):
        return {s: plain(getattr(v, s)) for s in v.__slots__}
    if isinstance(v, (list, tuple)):
        return [plain(x) for x in v]
    return v


# (a) python writes, we read.
python_bags = {}
for compression in ("none", "bz2", "lz4"):
    check(Imu._md5sum == "6a62c6daae103f4ff57a132d6f95cec2", "generated sensor_msgs/Imu has md5 %s" % Imu._md5sum)
    msgs = make_messages(seed=len(python_bags) + 1)
    path = os.path.join(work, "python_%s.bag" % compression)
    write_python_bag(path, compression, msgs)
    python_bags[compression] = (path, msgs)
    d = dump(path)
    info = d["info"]
    label = "python %s bag" % compression
    check(info["indexed"] and info["complete"], "%s: not read as indexed and complete: %s" % (label, info))
    check(info["compressions"] == [compression], "%s: compressions %s" % (label, info["compressions"]))
    check(info["message_count"] == len(msgs), "%s: message_count %d, wrote %d" % (label, info["message_count"], len(msgs)))
    check(info["chunk_count"] > 3, "%s: only %d chunks" % (label, info["chunk_count"]))
    check(info["start_ns"] == min(time_ns(t) for *_, t in msgs) and info["end_ns"] == max(time_ns(t) for *_, t in msgs),
          "%s: time range %d..%d" % (label, info["start_ns"], info["end_ns"]))
    by_topic = {c["topic"]: c for c in d["connections"]}
    check(len(d["connections"]) == len(TOPICS), "%s: %d connections" % (label, len(d["connections"])))
    for topic, cls in TOPICS:
        c = by_topic.get(topic)
        check(c is not None, "%s: no connection for %s" % (label, topic))
        check(c["type"] == cls._type and c["md5sum"] == cls._md5sum and c["message_definition"] == cls._full_text,
              "%s: connection %s is %s %s" % (label, topic, c["type"], c["md5sum"]))
    check(dumped_rows(d) == expected_rows(msgs), "%s: messages differ from those written" % label)
    print("ok: %s: %d messages in %d chunks" % (label, len(msgs), info["chunk_count"]))

# (b) a writer killed before close, and a bag cut mid-chunk: read by a scan.
for compression in ("none", "bz2", "lz4"):
    msgs = make_messages(seed=10)
    msgs += [m for m in make_messages(seed=11, n=200) if m[0] != "/blob/large"][:60]
    path = os.path.join(work, "killed_%s.bag" % compression)
    half = len(msgs) // 2
    pid = os.fork()
    if pid == 0:
        try:
            bag = rosbag.Bag(path, "w", compression=compression, chunk_threshold=64 * 1024)
            for topic, _, m, t in msgs[:half]:
                bag.write(topic, m, t)
            bag.flush()  # the chunks so far are complete on disk
            for topic, _, m, t in msgs[half:]:
                bag.write(topic, m, t)
        finally:  # the last, small messages are in a chunk still open

            os._exit(0)  # no close: no index, the open chunk unterminated, Python's buffer lost
    os.waitpid(pid, 0)
    label = "killed %s writer" % compression
    d = dump(path)
    info = d["info"]
    check(not info["indexed"], "%s: read as indexed" % label)
    n = check_prefix(d, msgs, label)
    check(n >= half, "%s: read %d messages, %d were flushed" % (label, n, half))
    size = os.path.getsize(path)
    if info["bytes_recovered"] < size:
        check(not info["complete"] and "byte offset %d" % info["bytes_recovered"] in info["detail"],
              "%s: stopped at %d of %d bytes but says %s" % (label, info["bytes_recovered"], size, info))
    print("ok: %s: %d of %d messages, %s" % (label, n, len(msgs), info["detail"]))

    full_path, full_msgs = python_bags[compression]
    data = open(full_path, "rb").read()
    cut = os.path.join(work, "cut_%s.bag" % compression)
    with open(cut, "wb") as f:
        f.write(data[:len(data) * 3 // 5])
    label = "python %s bag cut at 60%%" % compression
    d = dump(cut)
    info = d["info"]
    n = check_prefix(d, full_msgs, label)
    check(not info["complete"] and not info["indexed"] and 0 < n < len(full_msgs),
          "%s: %d messages, info %s" % (label, n, info))
    check("byte offset %d" % info["bytes_recovered"] in info["detail"], "%s: detail %r" % (label, info["detail"]))
    check(info["message_count"] == n, "%s: message_count %d, visited %d" % (label, info["message_count"], n))
    print("ok: %s: %d of %d messages, %s" % (label, n, len(full_msgs), info["detail"]))

check(dump(os.path.join(work, "missing.bag"), must_succeed=False) is None, "dump of a missing file succeeded")

# (c) we copy, python reads.
for source in ("none", "lz4"):
    src_path, msgs = python_bags[source]
    for compression in ("none", "bz2", "lz4"):
        label = "our %s copy of the python %s bag" % (compression, source)
        out = os.path.join(work, "copy_%s_to_%s.bag" % (source, compression))
        p = subprocess.run([dump_tool, "copy", src_path, out, "--compression", compression], capture_output=True, text=True)
        check(p.returncode == 0, "%s: copy exit %d: %s" % (label, p.returncode, p.stderr.strip()))
        with rosbag.Bag(out) as bag:
            check(bag.get_message_count() == len(msgs), "%s: python counts %d" % (label, bag.get_message_count()))
            types, topics = bag.get_type_and_topic_info()
            for topic, cls in TOPICS:
                check(types.get(cls._type) == cls._md5sum, "%s: type %s md5 %s" % (label, cls._type, types.get(cls._type)))
                want = sum(1 for m in msgs if m[0] == topic)
                check(topic in topics and topics[topic].msg_type == cls._type and topics[topic].message_count == want,
                      "%s: topic %s: %s" % (label, topic, topics.get(topic)))
            info = bag.get_compression_info()
            check(info.compression == compression, "%s: python sees compression %s" % (label, info.compression))
            got = list(bag.read_messages())
            check(len(got) == len(msgs), "%s: python reads %d messages" % (label, len(got)))
            # read_messages merges the connections' indexes, not strictly in time order (not
            # even for python's own bags): match each message to the original by topic and time.
            originals = {(topic, time_ns(t)): (cls, m) for topic, cls, m, t in msgs}
            check(len(originals) == len(msgs), "test messages do not have distinct topic and time")
            for r in got:
                cls, m = originals.pop((r.topic, time_ns(r.timestamp)), (None, None))
                check(m is not None, "%s: python reads an unexpected %s message at %s" % (label, r.topic, r.timestamp))
                check(r.message._type == cls._type and plain(r.message) == plain(m),
                      "%s: %s message at %s differs after deserialisation" % (label, r.topic, r.timestamp))
            raw = [serialized(m) for _, _, m, _ in msgs]
            got_raw = sorted(r.message[1] for r in bag.read_messages(raw=True))
            check(got_raw == sorted(raw), "%s: raw message bytes differ" % label)
        print("ok: %s: python reads all %d messages back" % (label, len(msgs)))

print("rosbag interop: all checks passed")
