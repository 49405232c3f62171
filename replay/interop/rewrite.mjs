// Rewrites an MCAP file with the official TypeScript writer (@mcap/core McapWriter) in one
// of its modes, keeping every record: schemas, channels, messages (log and publish time,
// sequence), attachments and metadata. Then reads the rewrite back with the official
// stream reader and checks that every record survived and that the mode took effect.
// Prints one JSON line describing the rewrite. Used by run_rewrite.sh.
//   node rewrite.mjs in.mcap out.mcap MODE
// MODE: default | nosummary | nochunks | lz4 | uncompressed | zstd
import { open, readFile } from "node:fs/promises";
import { McapStreamReader, McapWriter } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";
import zstd from "@foxglove/wasm-zstd";
import lz4 from "lz4js";
import { fileWritable } from "./file_writable.mjs";

const [, , inPath, outPath, mode] = process.argv;
const fail = (msg) => {
  console.error(`rewrite FAILED (${mode}: ${inPath} -> ${outPath}): ${msg}`);
  process.exit(1);
};

await zstd.isLoaded;
const modes = {
  // The writer as it comes: 1 MiB chunks, stored uncompressed; full summary and indexes.
  default: {},
  // What a recorder that never writes its summary leaves: no statistics, no repeated
  // schemas or channels, no indexes of any kind, no summary offsets (summary_start = 0).
  nosummary: {
    useStatistics: false,
    useSummaryOffsets: false,
    repeatSchemas: false,
    repeatChannels: false,
    useAttachmentIndex: false,
    useMetadataIndex: false,
    useMessageIndex: false,
    useChunkIndex: false,
  },
  // Every Schema, Channel and Message record in the data section itself.
  nochunks: { useChunks: false },
  // LZ4 frames from lz4js (no content size, linked blocks), as Foxglove's tools write them.
  lz4: { compressChunk: (data) => ({ compression: "lz4", compressedData: lz4.compress(data) }) },
  // Smaller chunks, explicitly stored without compression.
  uncompressed: { chunkSize: 256 * 1024, compressChunk: (data) => ({ compression: "", compressedData: data }) },
  zstd: { compressChunk: (data) => ({ compression: "zstd", compressedData: zstd.compress(data, 3) }) },
};
if (!(mode in modes)) fail(`unknown mode; one of ${Object.keys(modes).join(", ")}`);

const decompressHandlers = await loadDecompressHandlers();

// Every record of a file in order, chunks opened (Chunk records included).
function records(bytes) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true, includeChunks: true });
  reader.append(bytes);
  const out = [];
  for (let r; (r = reader.nextRecord()); ) out.push(r);
  if (!reader.done()) fail("the stream reader did not reach the footer");
  return out;
}

// What must survive a rewrite, with channel and schema ids replaced by their content.
function content(recs) {
  const schemas = new Map();
  const channels = new Map();
  const c = { header: undefined, schemas: new Set(), channels: new Set(), messages: [], attachments: [], metadata: [] };
  const text = (m) => JSON.stringify([...m.entries()].sort());
  for (const r of recs) {
    if (r.type === "Header") c.header = `${r.profile}`;
    else if (r.type === "Schema") {
      schemas.set(r.id, r);
      c.schemas.add(`${r.name}|${r.encoding}|${Buffer.from(r.data).toString("base64")}`);
    } else if (r.type === "Channel") {
      const s = schemas.get(r.schemaId);
      channels.set(r.id, `${r.topic}|${r.messageEncoding}|${s?.name}|${text(r.metadata)}`);
      c.channels.add(channels.get(r.id));
    } else if (r.type === "Message") {
      c.messages.push(`${channels.get(r.channelId)}|${r.sequence}|${r.logTime}|${r.publishTime}|` +
        Buffer.from(r.data).toString("base64"));
    } else if (r.type === "Attachment") {
      c.attachments.push(`${r.name}|${r.mediaType}|${r.logTime}|${r.createTime}|` + Buffer.from(r.data).toString("base64"));
    } else if (r.type === "Metadata") {
      c.metadata.push(`${r.name}|${text(r.metadata)}`);
    }
  }
  return c;
}

const input = records(new Uint8Array(await readFile(inPath)));

// Write: records in the input's order; schemas and channels are registered when met (the
// writer puts them in the data section, or inside the chunk, before their first message).
const file = await open(outPath, "w");
const writable = fileWritable(file);
const writer = new McapWriter({ writable, ...modes[mode] });
const schemaIds = new Map();
const channelIds = new Map();
for (const r of input) {
  switch (r.type) {
    case "Header":
      await writer.start({ profile: r.profile, library: `@mcap/core McapWriter (${mode}), rewriting ${r.library}` });
      break;
    case "Schema":
      if (!schemaIds.has(r.id))
        schemaIds.set(r.id, await writer.registerSchema({ name: r.name, encoding: r.encoding, data: r.data }));
      break;
    case "Channel":
      if (!channelIds.has(r.id))
        channelIds.set(r.id, await writer.registerChannel({
          topic: r.topic,
          messageEncoding: r.messageEncoding,
          schemaId: r.schemaId === 0 ? 0 : schemaIds.get(r.schemaId),
          metadata: r.metadata,
        }));
      break;
    case "Message":
      await writer.addMessage({ ...r, channelId: channelIds.get(r.channelId) });
      break;
    case "Attachment":
      await writer.addAttachment({ name: r.name, logTime: r.logTime, createTime: r.createTime, mediaType: r.mediaType, data: r.data });
      break;
    case "Metadata":
      await writer.addMetadata({ name: r.name, metadata: r.metadata });
      break;
    default:
      break;  // chunks, indexes, statistics, summary: the writer makes its own
  }
}
await writer.end();
await file.close();

// Read back: every record kept, and the mode visible in the file's structure.
const output = records(new Uint8Array(await readFile(outPath)));
const a = content(input);
const b = content(output);
const same = (x, y) => JSON.stringify(x) === JSON.stringify(y);
if (a.header !== b.header) fail(`profile ${b.header}, expected ${a.header}`);
if (!same([...a.schemas].sort(), [...b.schemas].sort())) fail("schemas differ");
if (!same([...a.channels].sort(), [...b.channels].sort())) fail("channels differ");
if (a.messages.length !== b.messages.length) fail(`${b.messages.length} messages, expected ${a.messages.length}`);
a.messages.forEach((m, i) => {
  if (m !== b.messages[i]) fail(`message ${i} differs`);
});
if (!same(a.attachments, b.attachments)) fail("attachments differ");
if (!same(a.metadata, b.metadata)) fail("metadata differ");
const chunks = output.filter((r) => r.type === "Chunk");
const compressions = [...new Set(chunks.map((r) => r.compression))];
const footer = output.find((r) => r.type === "Footer");
const fact = {
  mode,
  bytes: Number(writable.position()),
  chunks: chunks.length,
  compressions,
  summary: footer.summaryStart !== 0n,
  messages: b.messages.length,
  schemas: b.schemas.size,
  channels: b.channels.size,
  attachments: b.attachments.length,
  metadata: b.metadata.length,
};
const want = {
  default: () => fact.summary && fact.chunks > 0 && same(compressions, [""]),
  nosummary: () => !fact.summary && fact.chunks > 0 && !output.some((r) => ["MessageIndex", "ChunkIndex", "Statistics"].includes(r.type)),
  nochunks: () => fact.summary && fact.chunks === 0,
  lz4: () => fact.chunks > 0 && same(compressions, ["lz4"]),
  uncompressed: () => fact.chunks > 0 && same(compressions, [""]),
  zstd: () => fact.chunks > 0 && same(compressions, ["zstd"]),
};
if (!want[mode]()) fail(`the rewrite does not look like mode ${mode}: ${JSON.stringify(fact)}`);
console.log(JSON.stringify(fact));
