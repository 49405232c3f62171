// Reads an orthosonar fixture with the official TypeScript MCAP readers and decodes every
// message with Foxglove's ros1msg parser. Exit 0 when everything matches expected.json.
//   node check.mjs fixture.mcap expected.json
import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { parse } from "@foxglove/rosmsg";
import { MessageReader } from "@foxglove/rosmsg-serialization";
import { crc32 } from "@foxglove/crc";

const [, , path, expectedPath] = process.argv;
const bytes = new Uint8Array(await readFile(path));
const expected = JSON.parse(await readFile(expectedPath, "utf8"));
const decompressHandlers = await loadDecompressHandlers();
const fail = (msg) => {
  console.error(`interop FAILED (${path}): ${msg}`);
  process.exit(1);
};
const bump = (m, k) => (m[k] = (m[k] ?? 0) + 1);
const same = (a, b) => JSON.stringify(Object.entries(a).sort()) === JSON.stringify(Object.entries(b).sort());

// 1. The streaming reader: every record in file order, chunk CRCs validated.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const topics = new Map();
const streamCounts = {};
let dataEnd;
const streamAttachments = [];
for (let r; (r = stream.nextRecord()); ) {
  if (r.type === "Channel") topics.set(r.id, r.topic);
  else if (r.type === "Message") bump(streamCounts, topics.get(r.channelId));
  else if (r.type === "DataEnd") dataEnd = r;
  else if (r.type === "Attachment") streamAttachments.push(r.name);
}
if (!stream.done()) fail("stream reader did not reach the footer");
if (!dataEnd) fail("no Data End record");

// 2. The indexed reader: summary CRC checked at Initialize, chunk CRCs on read.
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
const dataCrc = crc32(bytes.subarray(0, Number(reader.dataEndOffset)));
if (reader.dataSectionCrc === undefined) fail("data section CRC not written");
if (dataCrc !== reader.dataSectionCrc) fail(`data section CRC ${dataCrc} != stored ${reader.dataSectionCrc}`);
if (dataEnd.dataSectionCrc !== dataCrc) fail("stream and indexed readers disagree on the data CRC");

const decoders = new Map();
for (const [id, s] of reader.schemasById) {
  if (s.encoding !== "ros1msg") fail(`schema ${s.name} has encoding ${s.encoding}`);
  decoders.set(id, new MessageReader(parse(new TextDecoder().decode(s.data))));
}
const counts = {};
let last = -1n;
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const ch = reader.channelsById.get(m.channelId);
  const schema = reader.schemasById.get(ch.schemaId);
  if (ch.messageEncoding !== "ros1") fail(`${ch.topic}: message encoding ${ch.messageEncoding}`);
  bump(counts, ch.topic);
  if (m.logTime < last) fail(`${ch.topic}: indexed reader went back in time`);
  last = m.logTime;
  const msg = decoders.get(ch.schemaId).readMessage(m.data);
  const where = `${ch.topic} sequence ${m.sequence}`;
  if (msg.header.seq !== m.sequence) fail(`${where}: header.seq ${msg.header.seq}`);
  const stampNs = BigInt(msg.header.stamp.sec) * 1000000000n + BigInt(msg.header.stamp.nsec);
  if (stampNs !== m.logTime) fail(`${where}: header stamp ${stampNs} != log time ${m.logTime}`);
  if (schema.name === "orthosonar_msgs/OculusPing") {
    const n = msg.rows * msg.cols * msg.bytes_per_pixel;
    if (msg.image.length !== n) fail(`${where}: image has ${msg.image.length} bytes, expected ${n}`);
    if (msg.bearings_rad.length !== msg.cols || msg.bearings.length !== msg.cols) fail(`${where}: bearings`);
    msg.bearings_rad.forEach((b, i) => {
      if (Math.abs(Math.round((b * 18000) / Math.PI) - msg.bearings[i]) > 1) fail(`${where}: bearing ${i}`);
    });
  } else if (schema.name === "sensor_msgs/Imu") {
    const q = msg.orientation;
    if (Math.abs(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w - 1) > 1e-9) fail(`${where}: quaternion norm`);
  } else if (schema.name === "orthosonar_msgs/SonarLabels") {
    const n = msg.rows * msg.cols;
    if (msg.semantic.length !== n || msg.object_id.length !== n) fail(`${where}: label sizes`);
  } else if (schema.name === "geometry_msgs/PoseStamped") {
    if (typeof msg.pose.position.x !== "number") fail(`${where}: pose`);
  }
}

const statsCounts = {};
for (const [id, n] of reader.statistics.channelMessageCounts) statsCounts[reader.channelsById.get(id).topic] = Number(n);
if (!same(counts, expected.counts)) fail(`indexed counts ${JSON.stringify(counts)} != ${JSON.stringify(expected.counts)}`);
if (!same(streamCounts, expected.counts)) fail(`stream counts ${JSON.stringify(streamCounts)}`);
if (!same(statsCounts, expected.counts)) fail(`statistics counts ${JSON.stringify(statsCounts)}`);
if (reader.chunkIndexes.length !== expected.chunks) fail(`${reader.chunkIndexes.length} chunks, expected ${expected.chunks}`);
const meta = [];
for await (const m of reader.readMetadata({ name: "orthosonar" })) meta.push(m);
if (meta.length !== 1 || meta[0].metadata.get("scene") !== expected.scene) fail("metadata record 'orthosonar'");

// 3. Attachments: found through the Attachment Index, CRCs checked, bytes as written.
const wantAtt = expected.attachments ?? [];
const atts = [];
for await (const a of reader.readAttachments({ validateCrcs: true })) atts.push(a);
if (atts.length !== wantAtt.length) fail(`${atts.length} attachments, expected ${wantAtt.length}`);
if (streamAttachments.length !== wantAtt.length) fail(`stream reader saw ${streamAttachments.length} attachments`);
if (reader.statistics.attachmentCount !== wantAtt.length) fail(`statistics attachment count ${reader.statistics.attachmentCount}`);
wantAtt.forEach((w, i) => {
  const a = atts[i];
  if (a.name !== w.name || a.mediaType !== w.media_type || a.logTime !== BigInt(w.log_time) || a.createTime !== 0n)
    fail(`attachment ${i}: ${a.name} ${a.mediaType} ${a.logTime}`);
  if (new TextDecoder().decode(a.data) !== w.text) fail(`attachment ${a.name}: data differs`);
});

const total = Object.values(counts).reduce((a, b) => a + b, 0);
console.log(`interop ok: ${total} messages on ${Object.keys(counts).length} topics, ` +
  `${reader.chunkIndexes.length} zstd chunks, ${atts.length} attachment(s), CRCs (chunks, attachments, data section, summary) valid`);
