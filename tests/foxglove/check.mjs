// Reads a BoP recording as Foxglove does and checks what Foxglove would show.
//   node check.mjs FILE.mcap [--flatc PATH] [--report OUT.json]
// 1. @mcap/core's indexed reader (the one seeking viewers use) and its stream reader each read
//    every message; both counts must equal the file's Statistics record, topic by topic.
// 2. Every schema named foxglove.* is compared, table by table and field by field (name, id,
//    type, default), with Foxglove's published definition: @foxglove/schemas generates its
//    FlatBuffers text and flatc compiles it to a binary schema.
// 3. Every message on a flatbuffer channel is decoded from its schema record, as Foxglove decodes
//    it (flatbuffers_reflection); foxglove.* messages are decoded with the published schema too and
//    must give the same object, and their content must make sense (points inside their stride,
//    finite coordinates, unit quaternions, named frames).
// Exit status 0 when all holds; the report lists the counts per topic.
import { McapIndexedReader, McapStreamReader } from "@mcap/core";
import { ByteBuffer } from "flatbuffers";
import { Parser, Schema, Table } from "flatbuffers_reflection";
import { decompress } from "fzstd";
import { execFileSync } from "node:child_process";
import { mkdtempSync, openSync, readFileSync, readSync, fstatSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { join } from "node:path";

const require = createRequire(import.meta.url);
const published = require("@foxglove/schemas/dist/internal/generateFlatbufferSchema.js");
const { foxgloveMessageSchemas } = require("@foxglove/schemas/dist/internal/schemas.js");

const args = process.argv.slice(2);
const opt = (name, fallback) => {
  const i = args.indexOf(name);
  return i >= 0 ? args.splice(i, 2)[1] : fallback;
};
const flatc = opt("--flatc", "flatc");
const reportPath = opt("--report", "");
if (args.length !== 1 || args[0].startsWith("-")) {
  console.error("usage: node check.mjs FILE.mcap [--flatc PATH] [--report OUT.json]");
  process.exit(2);
}
const file = args[0];
const failures = [];
const fail = (what) => {
  if (failures.length < 50) console.error(`FAIL ${what}`);
  failures.push(what);
};
const decompressHandlers = { zstd: (buf, size) => decompress(buf, new Uint8Array(Number(size))) };

// ---- 1. indexed and stream reading ----
const fd = openSync(file, "r");
const readable = {
  size: async () => BigInt(fstatSync(fd).size),
  read: async (offset, size) => {
    const out = new Uint8Array(Number(size));
    readSync(fd, out, 0, out.length, Number(offset));
    return out;
  },
};
const indexed = await McapIndexedReader.Initialize({ readable, decompressHandlers });
const topicOf = (id) => indexed.channelsById.get(id)?.topic ?? `#${id}`;
const perTopic = new Map();
const row = (topic) => {
  if (!perTopic.has(topic)) perTopic.set(topic, { indexed: 0, stream: 0, statistics: 0, decoded: 0, bytes: 0 });
  return perTopic.get(topic);
};
const messages = [];
for await (const m of indexed.readMessages()) {
  row(topicOf(m.channelId)).indexed++;
  row(topicOf(m.channelId)).bytes += m.data.length;
  messages.push(m);
}
const stream = new McapStreamReader({ decompressHandlers, validateCrcs: true });
stream.append(readFileSync(file));
for (let r; (r = stream.nextRecord()); ) if (r.type === "Message") row(topicOf(r.channelId)).stream++;
if (!stream.done()) fail("the stream reader did not reach the end of a complete file");
const stats = indexed.statistics;
if (!stats) fail("no Statistics record in the summary");
for (const [id, n] of stats?.channelMessageCounts ?? []) row(topicOf(id)).statistics = Number(n);
for (const [topic, r] of perTopic) {
  if (r.indexed !== r.statistics || r.stream !== r.statistics)
    fail(`${topic}: indexed reader ${r.indexed}, stream reader ${r.stream}, Statistics ${r.statistics} messages`);
}
if (indexed.chunkIndexes.length === 0) fail("no ChunkIndex records: the file is not indexed");
if (stats && indexed.chunkIndexes.length !== stats.chunkCount)
  fail(`${indexed.chunkIndexes.length} chunk indexes for ${stats.chunkCount} chunks`);

// ---- 2. foxglove.* schemas against the published definitions ----
const work = mkdtempSync(join(tmpdir(), "bop-foxglove-"));
writeFileSync(join(work, "Time.fbs"), published.TIME_FB);
writeFileSync(join(work, "Duration.fbs"), published.DURATION_FB);
writeFileSync(join(work, "ByteVector.fbs"), published.BYTE_VECTOR_FB);
for (const schema of Object.values(foxgloveMessageSchemas)) {
  if (schema.name === "Timestamp" || schema.name === "Duration") continue;  // the structs above
  const enums = [...new Map(schema.fields.filter((f) => f.type.type === "enum").map((f) => [f.type.enum.name, f.type.enum])).values()];
  writeFileSync(join(work, `${published.flatbufferMessageSchemaName(schema)}.fbs`), published.generateFlatbuffers(schema, enums));
}
const publishedSchema = (name) => {
  execFileSync(flatc, ["-b", "--schema", "-I", work, "-o", work, join(work, `${name}.fbs`)]);
  return readFileSync(join(work, `${name}.bfbs`));
};
const parseSchema = (bytes) => Schema.getRootAsSchema(new ByteBuffer(new Uint8Array(bytes)));
// A schema's tables and enums as plain objects, type references by name.
function describe(schema) {
  const objects = new Map(), enums = new Map();
  const typeName = (t) => {
    const base = t.baseType(), element = t.element(), index = t.index();
    if (index < 0) return { base, element };
    const isEnum = (base >= 1 && base <= 10) || (element >= 1 && element <= 10);
    return { base, element, ref: isEnum ? schema.enums(index).name() : schema.objects(index).name() };
  };
  for (let i = 0; i < schema.objectsLength(); i++) {
    const o = schema.objects(i), fields = {};
    for (let j = 0; j < o.fieldsLength(); j++) {
      const f = o.fields(j);
      fields[f.name()] = { id: f.id(), ...typeName(f.type()), int: String(f.defaultInteger()), real: f.defaultReal(), optional: f.optional() };
    }
    objects.set(o.name(), { struct: o.isStruct(), fields });
  }
  for (let i = 0; i < schema.enumsLength(); i++) {
    const e = schema.enums(i), values = {};
    for (let j = 0; j < e.valuesLength(); j++) values[e.values(j).name()] = String(e.values(j).value());
    enums.set(e.name(), values);
  }
  return { root: schema.rootTable()?.name(), objects, enums };
}
const json = (v) => JSON.stringify(v, (k, x) => (typeof x === "bigint" ? `${x}n` : x instanceof Uint8Array ? Array.from(x) : x));
const schemaReport = {};
const undecodable = {};  // schema name -> why Foxglove's decoder refuses it
const decoders = new Map();  // schema id -> { ours, published }
for (const [id, s] of indexed.schemasById) {
  if (s.encoding !== "flatbuffer") continue;
  const ours = parseSchema(s.data);
  let entry;
  try {
    entry = { ours: new Parser(ours).toObjectLambda(-1, true) };
  } catch (e) {
    // Foxglove's decoder takes no unions (BoP's Command): such a channel shows as raw bytes there.
    if (s.name.startsWith("foxglove.") || s.name.startsWith("bop.plot.")) fail(`${s.name}: ${e.message}`);
    undecodable[s.name] = e.message;
    continue;
  }
  if (s.name.startsWith("foxglove.")) {
    const short = s.name.slice("foxglove.".length);
    const theirs = describe(parseSchema(publishedSchema(short)));
    const mine = describe(ours);
    if (mine.root !== theirs.root) fail(`${s.name}: root table ${mine.root}, published ${theirs.root}`);
    let compared = 0;
    for (const [name, o] of theirs.objects) {
      if (json(mine.objects.get(name)) !== json(o)) fail(`${s.name}: table ${name} differs from the published one:\n  ours      ${json(mine.objects.get(name))}\n  published ${json(o)}`);
      compared++;
    }
    for (const [name, e] of theirs.enums) if (json(mine.enums.get(name)) !== json(e)) fail(`${s.name}: enum ${name} differs from the published one`);
    schemaReport[s.name] = `${compared} tables and ${theirs.enums.size} enums as published`;
    entry.published = new Parser(parseSchema(publishedSchema(short))).toObjectLambda(-1, true);
  }
  decoders.set(id, entry);
}

// ---- 3. every flatbuffer message decoded ----
const unit = (q) => Math.abs(Math.hypot(q.x ?? 0, q.y ?? 0, q.z ?? 0, q.w ?? 1) - 1) < 1e-6;
const frames = new Set();
const checks = {
  "foxglove.PointCloud": (m, where) => {
    const stride = m.point_stride, data = m.data ?? new Uint8Array();
    if (!(stride > 0) || data.length % stride !== 0) return fail(`${where}: ${data.length} bytes are not whole points of ${stride}`);
    const byName = Object.fromEntries((m.fields ?? []).map((f) => [f.name, f]));
    for (const axis of ["x", "y", "z"]) if (byName[axis]?.type !== 7) return fail(`${where}: no FLOAT32 field ${axis}`);
    for (const f of m.fields) if (f.offset + (f.type === 7 ? 4 : 1) > stride) fail(`${where}: field ${f.name} runs past the stride`);
    const view = new DataView(data.buffer, data.byteOffset, data.byteLength);
    for (let p = 0; p < data.length; p += stride)
      for (const axis of ["x", "y", "z"]) if (!Number.isFinite(view.getFloat32(p + byName[axis].offset, true))) return fail(`${where}: a coordinate is not finite`);
    frames.add(m.frame_id);
  },
  "foxglove.SceneUpdate": (m, where) => {
    for (const e of m.entities ?? []) {
      if (!e.id || !e.frame_id) fail(`${where}: an entity without id or frame`);
      frames.add(e.frame_id);
      for (const p of [...(e.cylinders ?? []), ...(e.spheres ?? []), ...(e.arrows ?? [])])
        if (!unit(p.pose?.orientation ?? {})) return fail(`${where}: a primitive's orientation is not a unit quaternion`);
    }
  },
  "foxglove.FrameTransform": (m, where) => {
    if (!m.parent_frame_id || !m.child_frame_id) fail(`${where}: a transform without its frames`);
    if (!unit(m.rotation ?? {})) fail(`${where}: the rotation is not a unit quaternion`);
    frames.add(m.parent_frame_id).add(m.child_frame_id);
  },
};
for (const m of messages) {
  const channel = indexed.channelsById.get(m.channelId);
  const schema = indexed.schemasById.get(channel.schemaId);
  const d = decoders.get(channel.schemaId);
  if (!d || channel.messageEncoding !== "flatbuffer") continue;
  const where = `${channel.topic} message ${m.sequence}`;
  let ours;
  try {
    ours = d.ours(Table.getRootTable(new ByteBuffer(m.data)));
    if (d.published) {
      const theirs = d.published(Table.getRootTable(new ByteBuffer(m.data)));
      if (json(ours) !== json(theirs)) fail(`${where}: decodes differently with the published schema`);
    }
  } catch (e) {
    fail(`${where}: does not decode with ${schema.name}: ${e.message}`);
    continue;
  }
  checks[schema.name]?.(ours, where);
  row(channel.topic).decoded++;
}

const report = {
  file,
  bytes: fstatSync(fd).size,
  chunks: indexed.chunkIndexes.length,
  compression: [...new Set(indexed.chunkIndexes.map((c) => c.compression || "none"))],
  seconds: stats ? Number(stats.messageEndTime - stats.messageStartTime) * 1e-9 : 0,
  schemas: schemaReport,
  undecodable,
  frames: [...frames].sort(),
  topics: Object.fromEntries(perTopic),
  failures: failures.length,
};
if (reportPath) writeFileSync(reportPath, JSON.stringify(report, null, 2) + "\n");
console.log(`${file}: ${report.bytes} bytes, ${report.chunks} chunks (${report.compression.join(", ")}), ${report.seconds.toFixed(2)} s recorded`);
for (const [name, what] of Object.entries(schemaReport)) console.log(`  schema ${name}: ${what}`);
for (const [name, why] of Object.entries(undecodable)) console.log(`  schema ${name}: not decodable by Foxglove's reader (${why})`);
console.log("  topic                      indexed   stream  decoded     bytes");
for (const [topic, r] of perTopic)
  console.log(`  ${topic.padEnd(26)} ${String(r.indexed).padStart(7)} ${String(r.stream).padStart(8)} ${String(r.decoded).padStart(8)} ${String(r.bytes).padStart(9)}`);
console.log(failures.length === 0 ? "foxglove check: all passed" : `foxglove check: ${failures.length} failures`);
process.exit(failures.length === 0 ? 0 : 1);
