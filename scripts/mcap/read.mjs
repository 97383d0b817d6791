// Reads an MCAP file back with @mcap/core's indexed reader and prints what it holds as JSON: the header's
// library, channels (topic, schema name and encoding, message encoding, message count), statistics (message
// count, first and last log times in ns, as strings), the metadata, and each topic's first and last message
// payload (parsed JSON). The MCAP round trip test reads this (tests/viewer/test_viewer_runs.py).
//   node read.mjs FILE.mcap
import { open } from "node:fs/promises";
import { McapIndexedReader } from "@mcap/core";

const path = process.argv[2];
const file = await open(path, "r");
const readable = {
  size: async () => BigInt((await file.stat()).size),
  async read(offset, size) {
    const buffer = new Uint8Array(Number(size));
    await file.read(buffer, 0, Number(size), Number(offset));
    return buffer;
  },
};
const reader = await McapIndexedReader.Initialize({ readable });
const decoder = new TextDecoder();
const counts = new Map();
const first = {}, last = {};
for await (const m of reader.readMessages()) {
  const topic = reader.channelsById.get(m.channelId).topic;
  counts.set(topic, (counts.get(topic) ?? 0) + 1);
  const payload = JSON.parse(decoder.decode(m.data));
  if (!(topic in first)) first[topic] = { log_time: String(m.logTime), payload };
  last[topic] = { log_time: String(m.logTime), payload };
}
const metadata = {};
for await (const md of reader.readMetadata()) metadata[md.name] = Object.fromEntries(md.metadata);
const channels = [...reader.channelsById.values()].map((c) => {
  const s = reader.schemasById.get(c.schemaId);
  return { topic: c.topic, message_encoding: c.messageEncoding, schema_name: s.name, schema_encoding: s.encoding,
           schema: decoder.decode(s.data), count: counts.get(c.topic) ?? 0 };
});
const st = reader.statistics;
console.log(JSON.stringify({ library: reader.header.library, channels,
  message_count: String(st.messageCount), message_start_time: String(st.messageStartTime),
  message_end_time: String(st.messageEndTime), metadata, first, last }));
await file.close();
