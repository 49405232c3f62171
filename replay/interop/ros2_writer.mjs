// A ROS 2 recording as rosbag2 writes one, made without orthosonar's code: reads an
// orthosonar fixture (ros1 messages, decoded by @foxglove/rosmsg-serialization from the
// schemas the file carries) and writes its sensor messages with the official TypeScript
// MCAP writer (@mcap/core McapWriter, lz4 chunks) as CDR (Foxglove's
// @foxglove/rosmsg2-serialization) in the authors' types, ROS 2 form, on the authors'
// topics. `orthosonar import` must read it (ctest ros:ros2-typescript-writer).
//   node ros2_writer.mjs fixture.mcap out.mcap
import { open, readFile } from "node:fs/promises";
import { McapStreamReader, McapWriter } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg-serialization";
import { MessageWriter } from "@foxglove/rosmsg2-serialization";
import lz4 from "lz4js";
import { fileWritable } from "./file_writable.mjs";

const [, , inPath, outPath] = process.argv;
const fail = (msg) => {
  console.error(`ros2_writer FAILED: ${msg}`);
  process.exit(1);
};

// ROS 2 definitions, written here from the packages' .msg files (independently of
// orthosonar's replay/ros/msg_types.cpp).
const SEP = "\n================================================================================\n";
const TIME = "MSG: builtin_interfaces/Time\nint32 sec\nuint32 nanosec";
const HEADER = "MSG: std_msgs/Header\nbuiltin_interfaces/Time stamp\nstring frame_id";
const VEC3 = "MSG: geometry_msgs/Vector3\nfloat64 x\nfloat64 y\nfloat64 z";
const QUAT = "MSG: geometry_msgs/Quaternion\nfloat64 x\nfloat64 y\nfloat64 z\nfloat64 w";
const defs = {
  "sonar_oculus/msg/OculusPingUncompressed": [
    "std_msgs/Header header\nOculusFire fire_msg\nuint32 ping_id\nuint16 part_number\nuint32 start_time\n" +
      "int16[] bearings\nfloat64 range_resolution\nuint32 num_ranges\nuint32 num_beams\nsensor_msgs/Image ping",
    HEADER, TIME,
    "MSG: sonar_oculus/OculusFire\nstd_msgs/Header header\nuint8 mode\nuint8 gamma\nuint8 flags\nfloat64 range\n" +
      "float64 gain\nfloat64 speed_of_sound\nfloat64 salinity",
    "MSG: sensor_msgs/Image\nstd_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\n" +
      "uint8 is_bigendian\nuint32 step\nuint8[] data",
  ].join(SEP),
  "sensor_msgs/msg/Imu": [
    "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n" +
      "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n" +
      "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance",
    HEADER, TIME, QUAT, VEC3,
  ].join(SEP),
  "rti_dvl/msg/DVL": [
    "std_msgs/Header header\ngeometry_msgs/Vector3 velocity\nfloat64 temperature\nfloat64 altitude\nfloat64 time",
    HEADER, TIME, VEC3,
  ].join(SEP),
  "kvh_gyro/msg/gyro": [
    "std_msgs/Header header\nbool status\nfloat64[] delta",
    HEADER, TIME,
  ].join(SEP),
  "bar30_depth/msg/Depth": [
    "std_msgs/Header header\nfloat32 time\nfloat32 pressure_abs\nfloat32 pressure_diff\nfloat32 temperature\nfloat32 depth",
    HEADER, TIME,
  ].join(SEP),
};

const decompressHandlers = await loadDecompressHandlers();
const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true });
reader.append(new Uint8Array(await readFile(inPath)));

const file = await open(outPath, "w");
const writable = fileWritable(file);
const writer = new McapWriter({
  writable,
  chunkSize: 512 * 1024,
  compressChunk: (data) => ({ compression: "lz4", compressedData: lz4.compress(data) }),
});
await writer.start({ profile: "ros2", library: "@mcap/core McapWriter (orthosonar ros2_writer.mjs)" });
const schemaIds = new Map(), outChannels = new Map(), writers = new Map();
for (const [name, text] of Object.entries(defs)) {
  schemaIds.set(name, await writer.registerSchema({ name, encoding: "ros2msg", data: new TextEncoder().encode(text) }));
  writers.set(name, new MessageWriter(parse(text, { ros2: true })));
}
async function channel(topic, type) {
  if (!outChannels.has(topic))
    outChannels.set(topic, await writer.registerChannel({ topic, messageEncoding: "cdr", schemaId: schemaIds.get(type), metadata: new Map() }));
  return outChannels.get(topic);
}

const schemas = new Map(), readers = new Map();
const stamp = (t) => ({ sec: t.sec, nanosec: t.nsec });
const counts = {};
let seq = 0;
for (let r; (r = reader.nextRecord()); ) {
  if (r.type === "Schema") schemas.set(r.id, r);
  if (r.type === "Channel") {
    const s = schemas.get(r.schemaId);
    readers.set(r.id, { topic: r.topic, read: new MessageReader(parse(new TextDecoder().decode(s.data))) });
  }
  if (r.type !== "Message") continue;
  const ch = readers.get(r.channelId);
  const m = ch.read.readMessage(r.data);
  const header = { stamp: stamp(m.header.stamp), frame_id: m.header.frame_id };
  let topic, type, out;
  if (ch.topic === "/sonar/horizontal/ping" || ch.topic === "/sonar/vertical/ping") {
    const h = ch.topic.startsWith("/sonar/horizontal");
    topic = h ? "/sonar_oculus_node/M750d/ping" : "/sonar_oculus_node/M1200d/ping";
    type = "sonar_oculus/msg/OculusPingUncompressed";
    const mode = m.frequency > (m.part_number === 1042 ? 2.0e6 : 1.0e6) ? 2 : 1;
    out = {
      header,
      fire_msg: { header, mode, gamma: 0, flags: 0, range: m.range_resolution * m.rows, gain: m.gain, speed_of_sound: 1500, salinity: 35 },
      ping_id: m.ping_id, part_number: m.part_number, start_time: 0,
      bearings: Int16Array.from(m.bearings), range_resolution: m.range_resolution,
      num_ranges: m.rows, num_beams: m.cols,
      ping: { header, height: m.rows, width: m.cols, encoding: m.bytes_per_pixel === 2 ? "mono16" : "mono8",
              is_bigendian: 0, step: m.cols * m.bytes_per_pixel, data: m.image },
    };
  } else if (ch.topic === "/imu/data") {
    topic = "/vn100/imu/raw"; type = "sensor_msgs/msg/Imu";
    out = { ...m, header };
  } else if (ch.topic === "/dvl/velocity") {
    topic = "/rti/body_velocity/raw"; type = "rti_dvl/msg/DVL";
    const v = m.valid ? m.velocity : { x: NaN, y: NaN, z: NaN };
    out = { header, velocity: v, temperature: 0, altitude: m.altitude, time: 0 };
  } else if (ch.topic === "/depth") {
    topic = "/bar30/depth/raw"; type = "bar30_depth/msg/Depth";
    out = { header, time: 0, pressure_abs: 0, pressure_diff: 0, temperature: 0, depth: m.depth };
  } else if (ch.topic === "/gyro") {
    // The authors' gyro_node: delta angles dx, dy, dz (rad) in the gyro's frame.
    if (m.is_rate) fail("a gyro rate: the authors' kvh_gyro/gyro carries delta angles");
    topic = "/gyro"; type = "kvh_gyro/msg/gyro";
    out = { header, status: m.status, delta: Float64Array.of(m.value.x, m.value.y, m.value.z) };
  } else {
    continue;  // truth and labels: not sensor data
  }
  const data = writers.get(type).writeMessage(out);
  await writer.addMessage({ channelId: await channel(topic, type), sequence: seq++, logTime: r.logTime, publishTime: r.logTime, data });
  counts[topic] = (counts[topic] ?? 0) + 1;
}
await writer.end();
await file.close();
// The five sensor topics, and the gyro when the mission has one (navigation profile paper).
const expected = 5 + (outChannels.has("/gyro") ? 1 : 0);
if (Object.keys(counts).length !== expected) fail(`wrote ${Object.keys(counts).length} topics, expected ${expected}: ${JSON.stringify(counts)}`);
console.log(JSON.stringify({ bytes: Number(writable.position()), counts }));
