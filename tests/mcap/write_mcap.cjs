#!/usr/bin/env node
// Writes MCAP files with npm's @mcap/core (Foxglove's reference writer, not the project's)
// for the reader's tests (reader_npm_test.cpp):
//   node write_mcap.cjs DIR
// DIR/KIND.mcap for each kind below, and DIR/KIND.expect.json: what a reader must find
// ({"messages": [{"topic", "log_time", "data"}], "metadata": {name: {key: value}}}, or
// {"error": WORDS} for a file it must refuse with those words).
// The @mcap packages come from NODE_PATH (tests/mcap/package.json: `npm ci`).
"use strict";

const fs = require("node:fs");
const path = require("node:path");
const { McapWriter, TempBuffer } = require("@mcap/core");
const zstd = require("@foxglove/wasm-zstd");

const KINDS = {
  // Chunked and zstd-compressed, with every index and the summary (as Foxglove writes).
  "zstd-chunks": { chunkSize: 2048, compression: "zstd" },
  // Chunks left uncompressed (compression ""), whose CRCs cover the plain records.
  "plain-chunks": { chunkSize: 2048, compression: "" },
  // No chunks at all: Schema, Channel and Message records straight in the data section.
  "no-chunks": { useChunks: false },
  // No summary: no statistics, indexes, repeated schemas or channels, summary offsets.
  "no-summary": { chunkSize: 2048, compression: "zstd", bare: true },
  // A compression this reader does not have.
  lz4: { chunkSize: 2048, compression: "lz4", error: "\"lz4\" is not supported" },
};

async function write(kind, options) {
  const buffer = new TempBuffer();
  const compressChunk = options.compression === undefined ? undefined : (data) => {
    if (options.compression === "zstd") return { compression: "zstd", compressedData: zstd.compress(data) };
    return { compression: options.compression, compressedData: data };
  };
  const bare = options.bare
    ? { useStatistics: false, useSummaryOffsets: false, repeatSchemas: false, repeatChannels: false,
        useAttachmentIndex: false, useMetadataIndex: false, useMessageIndex: false, useChunkIndex: false }
    : {};
  const writer = new McapWriter({ writable: buffer, useChunks: options.useChunks !== false,
    chunkSize: options.chunkSize, compressChunk, ...bare });
  await writer.start({ profile: "", library: "@mcap/core for wheeltec's tests" });
  const schema = await writer.registerSchema({ name: "wheeltec.Telemetry", encoding: "jsonschema",
    data: new TextEncoder().encode('{"type":"object"}') });
  const telemetry = await writer.registerChannel({ schemaId: schema, topic: "/telemetry", messageEncoding: "json",
    metadata: new Map() });
  const events = await writer.registerChannel({ schemaId: 0, topic: "/events", messageEncoding: "json",
    metadata: new Map([["source", "npm"]]) });
  const expect = { messages: [], metadata: {} };
  const start = 1790000000000000000n;
  for (let i = 0; i < 300; ++i) {
    const logTime = start + BigInt(i) * 20000000n;
    const record = i % 25 === 0 ? { channel: events, topic: "/events", data: `{"event":"mark","n":${i}}` }
                                : { channel: telemetry, topic: "/telemetry", data: `{"seq":${i},"velocity":{"vx":0.25}}` };
    await writer.addMessage({ channelId: record.channel, sequence: i, logTime, publishTime: logTime,
      data: new TextEncoder().encode(record.data) });
    expect.messages.push({ topic: record.topic, log_time: String(logTime), data: record.data });
  }
  await writer.addMetadata({ name: "wheeltec", metadata: new Map([["version", "0.1.0"], ["chassis", "mecanum"]]) });
  expect.metadata.wheeltec = { version: "0.1.0", chassis: "mecanum" };
  await writer.end();
  if (options.error) return { file: buffer.get(), expect: { error: options.error } };
  return { file: buffer.get(), expect };
}

async function main() {
  const dir = process.argv[2];
  if (!dir) { console.error("usage: write_mcap.cjs DIR"); process.exit(2); }
  await zstd.isLoaded;
  fs.mkdirSync(dir, { recursive: true });
  for (const [kind, options] of Object.entries(KINDS)) {
    const { file, expect } = await write(kind, options);
    fs.writeFileSync(path.join(dir, `${kind}.mcap`), file);
    fs.writeFileSync(path.join(dir, `${kind}.expect.json`), JSON.stringify(expect));
  }
  console.log(`wrote ${Object.keys(KINDS).length} files in ${dir}`);
}
main().catch((error) => { console.error(error); process.exit(1); });
