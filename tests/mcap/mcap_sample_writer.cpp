// Writes sample MCAP files for the read-back test with npm's @mcap readers:
//   mcap_sample_writer KIND FILE
// KIND: "drive" (five channels, many chunks, two metadata records), "ring" (chunks built
// ahead, copied in, then live messages), "empty" (channels, no message), or a drive with one
// byte changed: "corrupt-chunk" (in the first chunk's compressed records) or
// "corrupt-metadata" (in a metadata value, which only the data section's CRC covers).
// Next to FILE it writes FILE.expect.json: what read_mcap.cjs must find in it.

#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <string_view>

#include "wheeltec/mcap/chunk_builder.hpp"
#include "wheeltec/mcap/little_endian.hpp"
#include "wheeltec/mcap/writer.hpp"

namespace {

using wheeltec::mcap::Bytes;
using wheeltec::mcap::Registry;
using wheeltec::mcap::text_bytes;
using wheeltec::mcap::Writer;

constexpr std::uint64_t kMillisecond = 1'000'000;
constexpr std::uint64_t kStart = 1'790'000'000'000 * kMillisecond;

struct Channels {
  Registry registry;
  std::map<std::string, std::uint16_t> ids;  // by topic
};

Channels channels() {
  Channels c;
  const auto schema = [&](std::string_view name) {
    return c.registry.add_schema(std::string(name), "jsonschema", text_bytes(R"({"type":"object"})"));
  };
  const auto telemetry = schema("wheeltec.Telemetry");
  const auto status = schema("wheeltec.Status");
  const auto event = schema("wheeltec.Event");
  const auto pose = schema("foxglove.PoseInFrame");
  const auto transform = schema("foxglove.FrameTransform");
  c.ids["/telemetry"] = c.registry.add_channel(telemetry, "/telemetry", "json");
  c.ids["/status"] = c.registry.add_channel(status, "/status", "json");
  c.ids["/events"] = c.registry.add_channel(event, "/events", "json");
  c.ids["/odom"] = c.registry.add_channel(pose, "/odom", "json");
  c.ids["/tf"] = c.registry.add_channel(transform, "/tf", "json");
  return c;
}

// Counts what it writes, for the expectations.
class Recording {
 public:
  Recording(Bytes& file, const Channels& c) : c_(c), writer_(sink(file), c.registry, options()) {}

  void message(const std::string& topic, std::uint64_t time, const std::string& json) {
    writer_.write_message(c_.ids.at(topic), time, time, text_bytes(json));
    ++counts_[topic];
  }
  void chunk(const wheeltec::mcap::Chunk& chunk, const std::map<std::string, int>& counts) {
    writer_.write_chunk(chunk);
    for (const auto& [topic, count] : counts) counts_[topic] += count;
  }
  void metadata(const std::string& name, const wheeltec::mcap::Metadata& metadata) {
    writer_.write_metadata(name, metadata);
    metadata_[name] = metadata;
  }
  void finish() { writer_.finish(); }
  std::string expectations() const;

 private:
  static Writer::Sink sink(Bytes& file) {
    return [&file](wheeltec::mcap::ByteView bytes) { file.insert(file.end(), bytes.begin(), bytes.end()); };
  }
  static wheeltec::mcap::WriterOptions options() {
    return {.profile = "", .library = "wheeltec-mcap sample", .chunk_size = 8 * 1024};
  }

  const Channels& c_;
  Writer writer_;
  std::map<std::string, int> counts_;
  std::map<std::string, wheeltec::mcap::Metadata> metadata_;
};

// A JSON string of a text without control characters (the samples' texts).
std::string quoted(const std::string& text) {
  std::string json = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') json += '\\';
    json += c;
  }
  return json + "\"";
}

std::string Recording::expectations() const {
  int messages = 0;
  std::string channels;
  for (const auto& [topic, id] : c_.ids) {
    const int count = counts_.contains(topic) ? counts_.at(topic) : 0;
    messages += count;
    channels += (channels.empty() ? "" : ",") + quoted(topic) + ":" + std::to_string(count);
  }
  std::string metadata;
  for (const auto& [name, map] : metadata_) {
    std::string entries;
    for (const auto& [key, value] : map) entries += (entries.empty() ? "" : ",") + quoted(key) + ":" + quoted(value);
    metadata += (metadata.empty() ? "" : ",") + quoted(name) + ":{" + entries + "}";
  }
  return "{\"messages\":" + std::to_string(messages) + ",\"channels\":{" + channels + "},\"metadata\":{" + metadata +
         "}}\n";
}

void drive(Recording& r) {
  r.metadata("wheeltec", {{"version", "0.1.0"}, {"transport", "can"}, {"device", "vcan0"}, {"chassis", "mini_mec"}});
  for (std::uint64_t i = 0; i < 3000; ++i) {
    const std::uint64_t t = kStart + i * 20 * kMillisecond;
    const std::string seq = std::to_string(i);
    r.message("/telemetry", t, R"({"seq":)" + seq + R"(,"velocity":{"vx":0.2,"vy":0,"wz":0.1}})");
    r.message("/odom", t, R"({"frame_id":"odom","pose":{"position":{"x":)" + seq + "}}}");
    r.message("/tf", t, R"({"parent_frame_id":"odom","child_frame_id":"base_footprint","seq":)" + seq + "}");
    if (i % 50 == 0) r.message("/status", t + kMillisecond, R"({"phase":"ready"})");
    if (i % 700 == 0) r.message("/events", t + 2 * kMillisecond, R"({"event":"drive","vx":0.2})");
  }
  r.metadata("wheeltec.triggers", {{"triggers", R"([{"trigger":"mark","time":1790000030.0}])"}});
}

void ring(Recording& r, const Channels& c) {
  wheeltec::mcap::ChunkBuilder builder(c.registry);
  for (std::uint64_t second = 0; second < 10; ++second) {
    for (std::uint64_t i = 0; i < 50; ++i) {
      const std::uint64_t t = kStart + (second * 50 + i) * 20 * kMillisecond;
      builder.add_message(c.ids.at("/telemetry"), t, t, text_bytes(R"({"seq":)" + std::to_string(i) + "}"));
    }
    builder.add_message(c.ids.at("/status"), kStart + second * 1000 * kMillisecond + 3, 0, text_bytes("{}"));
    r.chunk(builder.finish(), {{"/telemetry", 50}, {"/status", 1}});
  }
  r.metadata("wheeltec", {{"triggers", R"([{"trigger":"deadman","time":1790000009.5}])"}});
  for (std::uint64_t i = 0; i < 100; ++i) r.message("/events", kStart + (10'000 + i) * kMillisecond, "{}");
}

// The offset of the first record with this opcode.
std::size_t first_record(const Bytes& file, std::uint8_t opcode) {
  std::size_t at = 8;  // after the magic
  while (std::to_integer<std::uint8_t>(file.at(at)) != opcode) {
    at += 9 + wheeltec::mcap::get_le<std::uint64_t>(file.data() + at + 1);
  }
  return at;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: mcap_sample_writer drive|ring|empty|corrupt-chunk|corrupt-metadata FILE\n";
    return 2;
  }
  const std::string kind = argv[1];
  const std::string path = argv[2];
  const Channels c = channels();
  Bytes file;
  Recording recording(file, c);
  if (kind == "drive" || kind.starts_with("corrupt-")) {
    drive(recording);
  } else if (kind == "ring") {
    ring(recording, c);
  } else if (kind != "empty") {
    std::cerr << "mcap_sample_writer: unknown kind " << kind << "\n";
    return 2;
  }
  recording.finish();
  if (kind == "corrupt-chunk") {
    const std::size_t chunk = first_record(file, 0x06);
    file[chunk + 9 + wheeltec::mcap::get_le<std::uint64_t>(file.data() + chunk + 1) / 2] ^= std::byte{0x01};
  } else if (kind == "corrupt-metadata") {
    // The last byte of the first Metadata record: its last value's last character.
    const std::size_t metadata = first_record(file, 0x0C);
    file[metadata + 9 + wheeltec::mcap::get_le<std::uint64_t>(file.data() + metadata + 1) - 1] ^= std::byte{0x01};
  }
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(file.data()),
                                               static_cast<std::streamsize>(file.size()));
  std::ofstream(path + ".expect.json") << recording.expectations();
  return 0;
}
