// Reads a file of orthosonar's GenericWriter (replay/mcap/mcap_generic.hpp) with non-ROS 1
// topics and encodings (cdr, json, a schemaless channel) with the official TypeScript
// MCAP readers, and checks every record against what the writer was given.
//   node generic_check.mjs generic.mcap   (expects generic.mcap.expected.json beside it)
import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import { crc32 } from "@foxglove/crc";

const [, , path] = process.argv;
const bytes = new Uint8Array(await readFile(path));
const expected = JSON.parse(await readFile(`${path}.expected.json`, "utf8"));
const decompressHandlers = await loadDecompressHandlers();
const fail = (msg) => {
  console.error(`generic interop FAILED (${path}): ${msg}`);
  process.exit(1);
};
const text = (data) => new TextDecoder().decode(data);
const want = expected.messages.map((m) => ({ ...m, log_time: BigInt(m.log_time), publish_time: BigInt(m.publish_time) }));
const sameMessage = (got, w, where) => {
  if (got.topic !== w.topic || got.sequence !== w.sequence || got.logTime !== w.log_time ||
      got.publishTime !== w.publish_time || text(got.data) !== w.data)
    fail(`${where}: ${got.topic} ${got.sequence} ${got.logTime} differs from ${JSON.stringify({ ...w, log_time: String(w.log_time), publish_time: String(w.publish_time) })}`);
};
const checkChannel = (ch, schema) => {
  const w = expected.channels[ch.topic];
  if (!w) fail(`unexpected channel ${ch.topic}`);
  if (ch.messageEncoding !== w.encoding) fail(`${ch.topic}: message encoding ${ch.messageEncoding}`);
  if ((schema?.name ?? "") !== w.schema || (schema?.encoding ?? "") !== w.schema_encoding)
    fail(`${ch.topic}: schema ${schema?.name} (${schema?.encoding})`);
  if (JSON.stringify(Object.fromEntries(ch.metadata)) !== JSON.stringify(w.metadata)) fail(`${ch.topic}: channel metadata`);
};

// 1. The streaming reader: every record in file order, chunk CRCs validated.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const schemas = new Map();
const channels = new Map();
let header, dataEnd, n = 0;
for (let r; (r = stream.nextRecord()); ) {
  if (r.type === "Header") header = r;
  else if (r.type === "Schema") schemas.set(r.id, r);
  else if (r.type === "Channel") channels.set(r.id, r);
  else if (r.type === "DataEnd") dataEnd = r;
  else if (r.type === "Message") {
    if (n >= want.length) fail("stream reader: too many messages");
    const ch = channels.get(r.channelId);
    sameMessage({ ...r, topic: ch.topic }, want[n], `stream message ${n}`);
    n++;
  }
}
if (!stream.done()) fail("stream reader did not reach the footer");
if (n !== want.length) fail(`stream reader: ${n} messages, expected ${want.length}`);
if (header.profile !== expected.profile) fail(`profile ${header.profile}`);
for (const ch of channels.values()) checkChannel(ch, schemas.get(ch.schemaId));

// 2. The indexed reader: summary CRC at Initialize, Chunk and Message Index records for
// log-time order, chunk CRCs on read, statistics, metadata and attachment indexes.
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
if (reader.dataSectionCrc === undefined) fail("data section CRC not written");
if (crc32(bytes.subarray(0, Number(reader.dataEndOffset))) !== reader.dataSectionCrc) fail("data section CRC");
if (dataEnd.dataSectionCrc !== reader.dataSectionCrc) fail("stream and indexed readers disagree on the data CRC");
for (const ch of reader.channelsById.values()) checkChannel(ch, reader.schemasById.get(ch.schemaId));
if (reader.channelsById.size !== Object.keys(expected.channels).length) fail(`${reader.channelsById.size} channels in the summary`);
const byTime = [...want].sort((a, b) => (a.log_time < b.log_time ? -1 : a.log_time > b.log_time ? 1 : 0));
let i = 0;
for await (const m of reader.readMessages({ validateCrcs: true })) {
  if (i >= byTime.length) fail("indexed reader: too many messages");
  sameMessage({ ...m, topic: reader.channelsById.get(m.channelId).topic }, byTime[i], `indexed message ${i}`);
  i++;
}
if (i !== byTime.length) fail(`indexed reader: ${i} messages, expected ${byTime.length}`);
const stats = reader.statistics;
if (Number(stats.messageCount) !== want.length) fail(`statistics: ${stats.messageCount} messages`);
if (stats.chunkCount !== reader.chunkIndexes.length || stats.chunkCount < 2) fail(`statistics: ${stats.chunkCount} chunks`);
if (stats.messageStartTime !== byTime[0].log_time || stats.messageEndTime !== byTime.at(-1).log_time)
  fail("statistics: message time range");
for (const [id, count] of stats.channelMessageCounts) {
  const topic = reader.channelsById.get(id).topic;
  if (Number(count) !== want.filter((m) => m.topic === topic).length) fail(`statistics: ${topic} count ${count}`);
}
const meta = [];
for await (const m of reader.readMetadata({ name: expected.metadata.name })) meta.push(m);
if (meta.length !== 1 || JSON.stringify(Object.fromEntries(meta[0].metadata)) !== JSON.stringify(expected.metadata.values))
  fail("metadata record");
const atts = [];
for await (const a of reader.readAttachments({ validateCrcs: true })) atts.push(a);
const wa = expected.attachment;
if (atts.length !== 1 || atts[0].name !== wa.name || atts[0].mediaType !== wa.media_type || text(atts[0].data) !== wa.text)
  fail("attachment");

console.log(`generic interop ok: ${want.length} messages on ${reader.channelsById.size} channels ` +
  `(${[...reader.channelsById.values()].map((c) => c.messageEncoding).join(", ")}), ${stats.chunkCount} chunks, ` +
  `metadata and attachment indexed, every CRC valid`);
