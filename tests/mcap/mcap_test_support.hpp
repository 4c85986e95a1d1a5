#pragma once

#include <string_view>

#include "wheeltec/mcap/registry.hpp"
#include "wheeltec/mcap/types.hpp"
#include "wheeltec/mcap/writer.hpp"

namespace mcap_test {

// The recorder's channels (spec section 10), a schema each; /events has channel metadata.
struct SampleChannels {
  wheeltec::mcap::Registry registry;
  std::uint16_t telemetry = 0;
  std::uint16_t status = 0;
  std::uint16_t events = 0;
  std::uint16_t odom = 0;
  std::uint16_t tf = 0;
};

inline SampleChannels sample_channels() {
  using wheeltec::mcap::text_bytes;
  SampleChannels s;
  auto& r = s.registry;
  const auto telemetry = r.add_schema("wheeltec.Telemetry", "jsonschema", text_bytes(R"({"type":"object"})"));
  const auto status = r.add_schema("wheeltec.Status", "jsonschema", text_bytes(R"({"type":"object"})"));
  const auto event = r.add_schema("wheeltec.Event", "jsonschema", text_bytes(R"({"type":"object"})"));
  const auto pose = r.add_schema("foxglove.PoseInFrame", "jsonschema", text_bytes(R"({"type":"object"})"));
  const auto transform = r.add_schema("foxglove.FrameTransform", "jsonschema", text_bytes(R"({"type":"object"})"));
  s.telemetry = r.add_channel(telemetry, "/telemetry", "json");
  s.status = r.add_channel(status, "/status", "json");
  s.events = r.add_channel(event, "/events", "json", {{"source", "wheeltecd"}});
  s.odom = r.add_channel(pose, "/odom", "json");
  s.tf = r.add_channel(transform, "/tf", "json");
  return s;
}

// A sink that appends to `out`.
inline wheeltec::mcap::Writer::Sink memory_sink(wheeltec::mcap::Bytes& out) {
  return [&out](wheeltec::mcap::ByteView bytes) { out.insert(out.end(), bytes.begin(), bytes.end()); };
}

}  // namespace mcap_test
