// ctest ros:msg-cdr-typescript (run by replay/ros/interop/msg_interop.sh): our ROS 2
// definition texts and CDR codec against Foxglove's independent implementation.
// For every type orthosonar knows (orthosonar_msg_dump types):
//   1. @foxglove/rosmsg parses our ROS 2 text (parse(text, { ros2: true }));
//   2. @foxglove/rosmsg2-serialization's MessageWriter serialises random messages; our
//      decoder must give the same values;
//   3. its MessageReader reads our Writer's sample message; the values must equal what our
//      decoder reads from the same bytes.
// Usage: node cdr_check.mjs <orthosonar_msg_dump> <work dir>
import { execFileSync, spawnSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";

import { parse } from "@foxglove/rosmsg";
import { MessageReader, MessageWriter } from "@foxglove/rosmsg2-serialization";

const [dump, work] = process.argv.slice(2);
fs.mkdirSync(work, { recursive: true });

// mulberry32: a seeded generator, so a failure repeats.
let seed = 20240518;
function rand() {
  seed = (seed + 0x6d2b79f5) | 0;
  let t = seed;
  t = Math.imul(t ^ (t >>> 15), t | 1);
  t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
  return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
}
const randInt = (lo, hi) => lo + Math.floor(rand() * (hi - lo + 1));

const INT_RANGES = {
  int8: [-128, 127], uint8: [0, 255], byte: [0, 255], char: [0, 255],
  int16: [-32768, 32767], uint16: [0, 65535],
  int32: [-(2 ** 31), 2 ** 31 - 1], uint32: [0, 2 ** 32 - 1],
};

function finite(bytes) {
  const buf = new DataView(new ArrayBuffer(8));
  for (;;) {
    for (let i = 0; i < bytes; i++) buf.setUint8(i, randInt(0, 255));
    const x = bytes === 4 ? buf.getFloat32(0, true) : buf.getFloat64(0, true);
    if (Number.isFinite(x)) return x;
  }
}

function randomScalar(type, defs) {
  if (type in INT_RANGES) return randInt(...INT_RANGES[type]);
  switch (type) {
    case "bool": return rand() < 0.5;
    case "float32": return finite(4);
    case "float64": return finite(8);
    case "int64": return BigInt(randInt(-(2 ** 40), 2 ** 40));
    case "uint64": return BigInt(randInt(0, 2 ** 40));
    case "string": {
      let s = "";
      for (let n = randInt(0, 12); n > 0; n--) s += String.fromCharCode(randInt(32, 126));
      return s;
    }
    case "time":
    case "duration":
      return { sec: randInt(0, 2 ** 31 - 1), nanosec: randInt(0, 999999999) };
    default:
      return randomMessage(defs.get(type), defs);
  }
}

function randomMessage(fields, defs) {
  const msg = {};
  for (const f of fields) {
    if (f.isConstant === true) continue;
    if (f.isArray !== true) {
      msg[f.name] = randomScalar(f.type, defs);
      continue;
    }
    const bytesLike = f.type === "uint8" || f.type === "byte" || f.type === "char";
    const n = f.arrayLength ?? randInt(0, bytesLike ? 40 : 6);
    const values = [];
    for (let i = 0; i < n; i++) values.push(randomScalar(f.type, defs));
    msg[f.name] = bytesLike ? Uint8Array.from(values) : values;
  }
  return msg;
}

function timeNs(v) {
  return BigInt(v.sec) * 1000000000n + BigInt(v.nanosec ?? v.nsec);
}

// Compares a message as Foxglove holds it with our decoder's JSON.
function compare(theirs, ours, type, isArray, defs, where, at) {
  if (where.length > 5) return;
  if (isArray) {
    const a = Array.from(theirs ?? []);
    if (!Array.isArray(ours) || a.length !== ours.length) {
      where.push(`${at}: length ${a.length} vs ${Array.isArray(ours) ? ours.length : JSON.stringify(ours)}`);
      return;
    }
    a.forEach((e, i) => compare(e, ours[i], type, false, defs, where, `${at}[${i}]`));
    return;
  }
  if (type === "time" || type === "duration") {
    if (ours == null || timeNs(theirs) !== timeNs(ours)) where.push(`${at}: ${JSON.stringify(theirs)} vs ${JSON.stringify(ours)}`);
  } else if (type === "bool") {
    if ((theirs ? 1 : 0) !== ours) where.push(`${at}: ${theirs} vs ${ours}`);
  } else if (type === "int64" || type === "uint64") {
    if (BigInt(theirs) !== BigInt(ours)) where.push(`${at}: ${theirs} vs ${ours}`);
  } else if (type in INT_RANGES || type === "float32" || type === "float64" || type === "string") {
    if (theirs !== ours) where.push(`${at}: ${theirs} vs ${ours}`);
  } else {
    const fields = defs.get(type);
    if (fields === undefined) {
      where.push(`${at}: no definition of ${type}`);
      return;
    }
    for (const f of fields) {
      if (f.isConstant === true) continue;
      if (ours == null || !(f.name in ours)) {
        where.push(`${at}.${f.name}: missing in ours`);
        continue;
      }
      compare(theirs?.[f.name], ours[f.name], f.type, f.isArray === true, defs, where, at ? `${at}.${f.name}` : f.name);
    }
  }
}

function oursDecode(name, file) {
  const r = spawnSync(dump, ["decode", name, "cdr", file], { encoding: "utf8" });
  if (r.status !== 0) return { error: (r.stderr || "").trim() || `exit ${r.status}` };
  return { value: JSON.parse(r.stdout) };
}

const types = JSON.parse(execFileSync(dump, ["types"], { encoding: "utf8" }));
const failures = [];
let compared = 0;
for (const t of types) {
  let definitions;
  try {
    definitions = parse(t.ros2, { ros2: true });
  } catch (e) {
    failures.push(`${t.name}: @foxglove/rosmsg cannot parse our ROS 2 text: ${e.message}`);
    continue;
  }
  const defs = new Map(definitions.map((d) => [d.name ?? "", d.definitions]));
  const root = definitions[0].definitions;
  defs.set(t.name, root);
  const stem = t.name.replace("/", "_");

  // 2. Foxglove writes, we read.
  const writer = new MessageWriter(definitions);
  for (let trial = 0; trial < 12; trial++) {
    const msg = randomMessage(root, defs);
    const file = path.join(work, `${stem}_${trial}.cdr`);
    fs.writeFileSync(file, writer.writeMessage(msg));
    const ours = oursDecode(t.name, file);
    if (ours.error) {
      failures.push(`${t.name} trial ${trial}: our decoder failed: ${ours.error}`);
      continue;
    }
    const where = [];
    compare(msg, ours.value, t.name, false, defs, where, "");
    for (const w of where) failures.push(`${t.name} trial ${trial}: ${w}`);
    compared++;
  }

  // 3. We write, Foxglove reads.
  const file = path.join(work, `${stem}_sample.cdr`);
  execFileSync(dump, ["encode-sample", t.name, "cdr", file]);
  const bytes = fs.readFileSync(file);
  let theirs;
  try {
    theirs = new MessageReader(definitions).readMessage(bytes);
  } catch (e) {
    failures.push(`${t.name}: MessageReader cannot read our sample: ${e.message}`);
    continue;
  }
  const ours = oursDecode(t.name, file);
  if (ours.error) {
    failures.push(`${t.name}: our decoder fails on our sample: ${ours.error}`);
    continue;
  }
  const where = [];
  compare(theirs, ours.value, t.name, false, defs, where, "");
  for (const w of where) failures.push(`${t.name} sample: ${w}`);
  // And Foxglove writes the same bytes back.
  const again = Buffer.from(writer.writeMessage(theirs));
  if (!again.equals(bytes)) failures.push(`${t.name}: MessageWriter re-serialises our sample differently (${again.length} vs ${bytes.length} bytes)`);
  compared++;
}

for (const f of failures) console.log(`FAIL: ${f}`);
console.log(`cdr interop: ${types.length} types, ${compared} messages compared, ${failures.length} mismatches`);
process.exit(failures.length === 0 ? 0 : 1);
