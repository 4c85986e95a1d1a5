#!/usr/bin/env node
// Reads an MCAP file with npm's readers of Foxglove's reference implementation and checks
// it as Foxglove would need it:
//   node read_mcap.cjs FILE [--expect EXPECT.json] [--require-crcs]
// - McapStreamReader (CRCs checked) reads every record from the first byte to the last and
//   must end on a whole file;
// - McapIndexedReader reads the summary (its CRC checked), then every message through the
//   chunk and message indexes, which must come in log-time order;
// - the data section's CRC, which neither reader checks, is checked here;
// - both readers must agree on each channel's message count, on the chunks and on the
//   metadata, and with the Statistics record.
// --require-crcs: every CRC (data section, summary, each chunk) must be filled in.
// --expect: a JSON object whose keys must equal the same keys of the summary printed.
// Prints {"messages", "channels": {topic: count}, "schemas": [names], "metadata": {name:
// {key: value}}, "chunks", "crcs"} on stdout. Exit 0: all is well; 3: the file is invalid or
// differs from the expectations (the reason on stderr); 2: usage.
// The @mcap packages come from NODE_PATH (tests/mcap/package.json: `npm ci`).
"use strict";

const fs = require("node:fs");
const { McapIndexedReader, McapStreamReader } = require("@mcap/core");
const { loadDecompressHandlers } = require("@mcap/support");
const { FileHandleReadable } = require("@mcap/nodejs");
const { crc32Final, crc32Init, crc32Update } = require("@foxglove/crc");

const PIECE = 1 << 20;

function check(condition, message) {
  if (!condition) throw new Error(message);
}

// JSON with sorted keys: two values are equal when their canonical texts are.
function canonical(value) {
  if (Array.isArray(value)) return `[${value.map(canonical).join(",")}]`;
  if (value !== null && typeof value === "object") {
    return `{${Object.keys(value).sort().map((key) => `${JSON.stringify(key)}:${canonical(value[key])}`).join(",")}}`;
  }
  return JSON.stringify(value);
}

function parseArguments(argv) {
  const options = { file: undefined, expect: undefined, requireCrcs: false };
  for (let i = 0; i < argv.length; ++i) {
    if (argv[i] === "--expect" && i + 1 < argv.length) options.expect = argv[++i];
    else if (argv[i] === "--require-crcs") options.requireCrcs = true;
    else if (!argv[i].startsWith("--") && options.file === undefined) options.file = argv[i];
    else return undefined;
  }
  return options.file === undefined ? undefined : options;
}

// Calls visit(bytes) for the file's bytes [0, end) in order.
async function readPieces(file, end, visit) {
  const handle = await fs.promises.open(file, "r");
  try {
    for (let offset = 0; offset < end; ) {
      const buffer = Buffer.alloc(Math.min(PIECE, end - offset));
      const { bytesRead } = await handle.read(buffer, 0, buffer.length, offset);
      check(bytesRead > 0, `${file} ends before byte ${end}`);
      visit(buffer.subarray(0, bytesRead));
      offset += bytesRead;
    }
  } finally {
    await handle.close();
  }
}

async function streamRead(file, decompressHandlers) {
  const reader = new McapStreamReader({ decompressHandlers, validateCrcs: true, includeChunks: true });
  const read = { topics: new Map(), counts: new Map(), metadata: {}, chunks: 0, chunksWithoutCrc: 0 };
  const size = (await fs.promises.stat(file)).size;
  await readPieces(file, size, (bytes) => {
    reader.append(bytes);
    for (let record; (record = reader.nextRecord()); ) {
      if (record.type === "Channel") read.topics.set(record.id, record.topic);
      else if (record.type === "Message") {
        check(read.topics.has(record.channelId), `a message on channel ${record.channelId} before its Channel record`);
        read.counts.set(record.channelId, (read.counts.get(record.channelId) ?? 0) + 1);
      } else if (record.type === "Chunk") {
        ++read.chunks;
        if (record.uncompressedCrc === 0) ++read.chunksWithoutCrc;
      } else if (record.type === "Metadata") read.metadata[record.name] = Object.fromEntries(record.metadata);
    }
  });
  check(reader.done(), "the stream reader did not reach the end of a whole file");
  return read;
}

async function indexedRead(file, decompressHandlers) {
  const handle = await fs.promises.open(file, "r");
  try {
    const reader = await McapIndexedReader.Initialize({ readable: new FileHandleReadable(handle), decompressHandlers });
    const counts = new Map();
    let lastLogTime = -1n;
    for await (const message of reader.readMessages()) {
      check(message.logTime >= lastLogTime, `the indexed reader's messages go back in time at ${message.logTime}`);
      lastLogTime = message.logTime;
      counts.set(message.channelId, (counts.get(message.channelId) ?? 0) + 1);
    }
    const metadata = {};
    for await (const record of reader.readMetadata()) metadata[record.name] = Object.fromEntries(record.metadata);
    return { reader, counts, metadata };
  } finally {
    await handle.close();
  }
}

async function dataSectionCrc(file, reader) {
  if (reader.dataSectionCrc === undefined) return "absent";
  let crc = crc32Init();
  await readPieces(file, Number(reader.dataEndOffset), (bytes) => {
    crc = crc32Update(crc, bytes);
  });
  crc = crc32Final(crc);
  check(crc === reader.dataSectionCrc, `incorrect data section CRC ${crc} (expected ${reader.dataSectionCrc})`);
  return "ok";
}

function checkStatistics(reader, counts, total) {
  const statistics = reader.statistics;
  if (statistics === undefined) return;
  check(Number(statistics.messageCount) === total,
    `Statistics count ${statistics.messageCount} messages, not ${total}`);
  check(statistics.chunkCount === reader.chunkIndexes.length, "Statistics count another number of chunks");
  check(statistics.metadataCount === reader.metadataIndexes.length, "Statistics count another number of metadata");
  for (const [channelId, count] of statistics.channelMessageCounts) {
    check(Number(count) === (counts.get(channelId) ?? 0), `Statistics count ${count} messages on channel ${channelId}`);
  }
}

function perTopic(topics, counts) {
  const result = {};
  for (const [channelId, topic] of topics) result[topic] = (result[topic] ?? 0) + (counts.get(channelId) ?? 0);
  return result;
}

async function readMcap(options) {
  const decompressHandlers = await loadDecompressHandlers();
  const stream = await streamRead(options.file, decompressHandlers);
  const indexed = await indexedRead(options.file, decompressHandlers);
  const reader = indexed.reader;
  const indexedTopics = new Map([...reader.channelsById].map(([id, channel]) => [id, channel.topic]));
  const channels = perTopic(indexedTopics, indexed.counts);
  check(canonical(perTopic(stream.topics, stream.counts)) === canonical(channels),
    "the stream reader and the indexed reader count other messages per channel");
  check(stream.chunks === reader.chunkIndexes.length,
    `${stream.chunks} chunks but ${reader.chunkIndexes.length} Chunk Indexes`);
  check(canonical(stream.metadata) === canonical(indexed.metadata), "the readers find other metadata");
  const messages = [...indexed.counts.values()].reduce((sum, count) => sum + count, 0);
  checkStatistics(reader, indexed.counts, messages);

  const crcs = {
    data_section: await dataSectionCrc(options.file, reader),
    summary: reader.footer.summaryCrc === 0 ? "absent" : "ok",
    chunks: stream.chunksWithoutCrc === 0 ? "ok" : `${stream.chunksWithoutCrc} absent`,
  };
  if (options.requireCrcs) {
    for (const [what, state] of Object.entries(crcs)) check(state === "ok", `the ${what} CRC is not filled in`);
  }
  const schemas = [...reader.schemasById.values()].sort((a, b) => a.id - b.id).map((schema) => schema.name);
  return { messages, channels, schemas, metadata: indexed.metadata, chunks: reader.chunkIndexes.length, crcs };
}

async function main() {
  const options = parseArguments(process.argv.slice(2));
  if (options === undefined) {
    process.stderr.write("usage: node read_mcap.cjs FILE [--expect EXPECT.json] [--require-crcs]\n");
    return 2;
  }
  try {
    const summary = await readMcap(options);
    process.stdout.write(`${JSON.stringify(summary)}\n`);
    if (options.expect !== undefined) {
      const expected = JSON.parse(fs.readFileSync(options.expect, "utf8"));
      for (const key of Object.keys(expected)) {
        check(canonical(summary[key]) === canonical(expected[key]),
          `${key} is ${canonical(summary[key])}, expected ${canonical(expected[key])}`);
      }
    }
    return 0;
  } catch (error) {
    process.stderr.write(`read_mcap: ${options.file}: ${error.message}\n`);
    return 3;
  }
}

main().then((code) => {
  process.exitCode = code;
});
