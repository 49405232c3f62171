// Reads a run's results.mcap (replay/run/results_mcap.hpp) with the official TypeScript MCAP
// readers, decodes every message as Foxglove does (JSON.parse; base64 bytes where the schema
// says contentEncoding base64) and validates it against the JSON schema stored in the file:
// required keys, types, integer bounds, enum consts. Then the content: a PointCloud's bytes
// hold whole points of finite float32 x y z, as many as the metadata says; quaternions
// are unit; triangle indices are in range. Prints one line per topic; exit 0 when all pass.
//   node results_check.mjs results.mcap [--maps-nonempty] [topic ...]
// (the topics that must be present; --maps-nonempty: every map holds at least one point)
import { readFile } from "node:fs/promises";
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { loadDecompressHandlers } from "@mcap/support";

const [, , path, ...rest] = process.argv;
const mapsNonempty = rest.includes("--maps-nonempty");
const expectedTopics = rest.filter((a) => a !== "--maps-nonempty");
const bytes = new Uint8Array(await readFile(path));
const decompressHandlers = await loadDecompressHandlers();
const fail = (msg) => {
  console.error(`results check FAILED (${path}): ${msg}`);
  process.exit(1);
};
const bump = (m, k) => (m[k] = (m[k] ?? 0) + 1);

// 1. The streaming reader: every record in file order, chunk CRCs validated.
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(bytes);
const streamTopics = new Map();
const streamCounts = {};
const metadata = new Map();
for (let r; (r = stream.nextRecord()); ) {
  if (r.type === "Channel") streamTopics.set(r.id, r.topic);
  else if (r.type === "Message") bump(streamCounts, streamTopics.get(r.channelId));
  else if (r.type === "Metadata") metadata.set(r.name, r.metadata);
}
if (!stream.done()) fail("stream reader did not reach the footer");
const info = metadata.get("orthosonar");
if (!info) fail('no Metadata record "orthosonar"');
for (const key of ["software_version", "digest", "systems"]) if (!info.has(key)) fail(`metadata lacks ${key}`);
if (!/^[0-9a-f]{64}$/.test(info.get("digest"))) fail(`metadata digest ${info.get("digest")}`);

// 2. The indexed reader: summary and chunk CRCs, messages in log-time order.
const readable = {
  size: async () => BigInt(bytes.length),
  read: async (offset, length) => bytes.subarray(Number(offset), Number(offset + length)),
};
const reader = await McapIndexedReader.Initialize({ readable, decompressHandlers });
const schemas = new Map();
for (const [id, s] of reader.schemasById) {
  if (s.encoding !== "jsonschema") fail(`schema ${s.name} has encoding ${s.encoding}`);
  const schema = JSON.parse(new TextDecoder().decode(s.data));
  if (schema.title !== s.name) fail(`schema ${s.name} has title ${schema.title}`);
  schemas.set(id, schema);
}
const indexedMetadata = reader.metadataIndexes.map((m) => m.name);
if (!indexedMetadata.includes("orthosonar")) fail("the summary does not index the orthosonar metadata");

// A JSON-schema check of the subset the Foxglove schemas use.
const typeOk = {
  object: (v) => v !== null && typeof v === "object" && !Array.isArray(v),
  array: Array.isArray,
  string: (v) => typeof v === "string",
  number: (v) => typeof v === "number" && Number.isFinite(v),
  integer: Number.isInteger,
  boolean: (v) => typeof v === "boolean",
};
function validate(value, schema, where) {
  if (schema.type && !typeOk[schema.type](value)) fail(`${where}: ${JSON.stringify(value)?.slice(0, 40)} is not ${schema.type}`);
  if (schema.minimum !== undefined && value < schema.minimum) fail(`${where}: ${value} < ${schema.minimum}`);
  if (schema.maximum !== undefined && value > schema.maximum) fail(`${where}: ${value} > ${schema.maximum}`);
  if (schema.oneOf && !schema.oneOf.some((c) => c.const === value)) fail(`${where}: ${value} is none of the enum`);
  if (schema.contentEncoding === "base64") {
    if (!/^[A-Za-z0-9+/]*={0,2}$/.test(value) || value.length % 4 !== 0) fail(`${where}: not base64`);
  }
  for (const key of schema.required ?? []) if (!(key in value)) fail(`${where}: required ${key} missing`);
  if (schema.properties && typeOk.object(value))
    for (const [key, sub] of Object.entries(schema.properties)) if (key in value) validate(value[key], sub, `${where}.${key}`);
  if (schema.items && Array.isArray(value)) value.forEach((v, i) => validate(v, schema.items, `${where}[${i}]`));
}
const unitQuat = (q, where) => {
  const n = Math.hypot(q.x, q.y, q.z, q.w);
  if (Math.abs(n - 1) > 1e-9) fail(`${where}: quaternion norm ${n}`);
};
const stampNs = (t) => BigInt(t.sec) * 1000000000n + BigInt(t.nsec);

const counts = {};
const detail = {};
const schemaOf = {};
let last = -1n;
for await (const m of reader.readMessages({ validateCrcs: true })) {
  const ch = reader.channelsById.get(m.channelId);
  const schema = schemas.get(ch.schemaId);
  if (ch.messageEncoding !== "json") fail(`${ch.topic}: message encoding ${ch.messageEncoding}`);
  if (m.logTime < last) fail(`${ch.topic}: indexed reader went back in time`);
  last = m.logTime;
  bump(counts, ch.topic);
  schemaOf[ch.topic] = schema.title;
  const where = `${ch.topic} #${m.sequence}`;
  let msg;
  try {
    msg = JSON.parse(new TextDecoder().decode(m.data));
  } catch (e) {
    fail(`${where}: not JSON (${e.message})`);
  }
  validate(msg, schema, where);
  const d = (detail[ch.topic] ??= {});
  switch (schema.title) {
    case "foxglove.PointCloud": {
      const data = Buffer.from(msg.data, "base64");
      const names = msg.fields.map((f) => `${f.name}@${f.offset}:${f.type}`).join(" ");
      if (names !== "x@0:7 y@4:7 z@8:7" || msg.point_stride !== 12) fail(`${where}: fields ${names}, stride ${msg.point_stride}`);
      if (data.length % msg.point_stride !== 0) fail(`${where}: ${data.length} bytes is not whole points`);
      const n = data.length / msg.point_stride;
      for (let i = 0; i < n * 3; i++) if (!Number.isFinite(data.readFloatLE(i * 4))) fail(`${where}: value ${i} not finite`);
      const system = ch.topic.split("/")[2];
      const declared = info.get(`map_points.${system}`);
      if (declared === undefined || Number(declared) !== n) fail(`${where}: ${n} points, metadata says ${declared}`);
      if (mapsNonempty && n === 0) fail(`${where}: no points`);
      if (stampNs(msg.timestamp) !== m.logTime) fail(`${where}: timestamp != log time`);
      d.text = `${n} points (${data.length} bytes), frame ${msg.frame_id}`;
      break;
    }
    case "foxglove.PosesInFrame": {
      msg.poses.forEach((p, i) => unitQuat(p.orientation, `${where} pose ${i}`));
      if (msg.poses.length === 0) fail(`${where}: no poses`);
      d.text = `${msg.poses.length} poses, frame ${msg.frame_id}`;
      break;
    }
    case "foxglove.FrameTransform": {
      unitQuat(msg.rotation, where);
      if (stampNs(msg.timestamp) !== m.logTime) fail(`${where}: timestamp != log time`);
      (d.children ??= {})[`${msg.parent_frame_id}->${msg.child_frame_id}`] = true;
      d.text = `frames ${Object.keys(d.children).sort().join(", ")}`;
      break;
    }
    case "foxglove.SceneUpdate": {
      let tris = 0;
      for (const e of msg.entities)
        for (const t of e.triangles) {
          if (t.indices.length % 3 !== 0) fail(`${where}: ${t.indices.length} indices`);
          for (const i of t.indices) if (!Number.isInteger(i) || i < 0 || i >= t.points.length) fail(`${where}: index ${i}`);
          tris += t.indices.length / 3;
        }
      d.text = `${msg.entities.length} entit${msg.entities.length === 1 ? "y" : "ies"}, ${tris} triangles`;
      break;
    }
    default:
      fail(`${where}: unexpected schema ${schema.title}`);
  }
}
for (const topic of new Set([...Object.keys(counts), ...Object.keys(streamCounts)]))
  if (counts[topic] !== streamCounts[topic]) fail(`${topic}: indexed ${counts[topic]} vs streamed ${streamCounts[topic]} messages`);
for (const topic of expectedTopics) if (!counts[topic]) fail(`expected topic ${topic} is missing`);
for (const system of info.get("systems").split(",").filter(Boolean))
  if (!counts[`/orthosonar/${system}/map`]) fail(`no map for system ${system}`);

for (const topic of Object.keys(counts).sort())
  console.log(`${topic}  ${schemaOf[topic]}  ${counts[topic]} message(s)  ${detail[topic].text}`);
console.log(`results.mcap OK: ${bytes.length} bytes, ${Object.keys(counts).length} topics, digest ${info.get("digest")}`);
