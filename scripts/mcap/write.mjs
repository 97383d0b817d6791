// swarm export --mcap: an MCAP file (@mcap/core, scripts/mcap/README.md) of the lines `swarm_viewer
// --export-frames RUN_DIR` writes on stdin: serverInfo, advertise (the live server's channels and schemas),
// {"op": "range", ...}, then one message a line: CHANNEL LOG_TIME_NS TICK PAYLOAD.
//   node write.mjs OUT.mcap [--run-dir DIR]      progress on stderr every 2 s; OUT.mcap appears whole or not at all
import { open, rename, unlink } from "node:fs/promises";
import { createInterface } from "node:readline";
import { McapWriter } from "@mcap/core";

const out = process.argv[2];
const runDir = process.argv[3] === "--run-dir" ? process.argv[4] : "";
if (!out) {
  console.error("write.mjs: usage: node write.mjs OUT.mcap [--run-dir DIR] < lines");
  process.exit(2);
}
const tmp = `${out}.tmp`;
const file = await open(tmp, "w");
let position = 0n;
const writable = {
  position: () => position,
  async write(buffer) {
    await file.write(buffer);
    position += BigInt(buffer.byteLength);
  },
};
const writer = new McapWriter({ writable, useStatistics: true, useSummaryOffsets: true, useChunks: true,
                                useChunkIndex: true, useMessageIndex: true });
const encoder = new TextEncoder();
const channels = new Map(); // the live server's channel id -> this file's
const sequence = new Map();
let range = null;
let count = 0;
let lineNo = 0;
let last = Date.now();
const fail = async (message) => {
  console.error(`swarm export: ${message}`);
  await file.close();
  await unlink(tmp).catch(() => {});
  process.exit(1);
};

await writer.start({ profile: "", library: "swarmform swarm export (@mcap/core)" });
const lines = createInterface({ input: process.stdin, crlfDelay: Infinity });
for await (const line of lines) {
  ++lineNo;
  if (lineNo <= 3) {
    const m = JSON.parse(line);
    if (m.op === "advertise") {
      for (const c of m.channels) {
        const schemaId = await writer.registerSchema({ name: c.schemaName, encoding: c.schemaEncoding,
                                                       data: encoder.encode(c.schema) });
        channels.set(c.id, await writer.registerChannel({ topic: c.topic, messageEncoding: c.encoding, schemaId,
                                                          metadata: new Map() }));
      }
    } else if (m.op === "range") {
      range = m;
      await writer.addMetadata({ name: "swarmform", metadata: new Map([
        ["run_dir", runDir], ["first_tick", String(m.first_tick)], ["last_tick", String(m.last_tick)],
        ["tick_rate", String(m.tick_rate)]]) });
    }
    continue;
  }
  const a = line.indexOf(" "), b = line.indexOf(" ", a + 1), c = line.indexOf(" ", b + 1);
  const channel = channels.get(Number(line.slice(0, a)));
  if (a < 0 || b < 0 || c < 0 || channel === undefined) await fail(`line ${lineNo} of the viewer's output: not a message`);
  const logTime = BigInt(line.slice(a + 1, b));
  const seq = (sequence.get(channel) ?? 0) + 1;
  sequence.set(channel, seq);
  await writer.addMessage({ channelId: channel, sequence: seq, logTime, publishTime: logTime,
                            data: encoder.encode(line.slice(c + 1)) });
  ++count;
  if (Date.now() - last >= 2000 && range) {
    last = Date.now();
    const tick = Number(line.slice(b + 1, c));
    const span = Math.max(1, range.last_tick - range.first_tick);
    console.error(`swarm export: tick ${tick} of ${range.last_tick} (${Math.round(100 * (tick - range.first_tick) / span)} %), ${count} messages`);
  }
}
if (channels.size === 0 || range === null) await fail("the viewer wrote no channels (see its message above)");
await writer.end();
await file.close();
await rename(tmp, out);
console.error(`swarm export: ${out}: ${count} messages on ${channels.size} channels, ticks ${range.first_tick}..${range.last_tick}`);
