#include "record_messages.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/mcap/writer.hpp"

namespace wheeltec::web {
namespace {

using mcap::text_bytes;

// A file as wheeltec-record writes it: its channels, the metadata record, and messages whose
// log times are not in file order.
mcap::Bytes recorded(const std::string& odd_event = R"({"time":3.0,"event":"mark","client":2})") {
  mcap::Registry registry;
  const auto schema = registry.add_schema("wheeltec.Telemetry", "jsonschema", text_bytes("{}"));
  const auto telemetry = registry.add_channel(schema, "/telemetry", "json");
  const auto status = registry.add_channel(schema, "/status", "json");
  const auto events = registry.add_channel(schema, "/events", "json");
  const auto odom = registry.add_channel(schema, "/odom", "json");
  mcap::Bytes file;
  mcap::Writer writer([&file](mcap::ByteView bytes) { file.insert(file.end(), bytes.begin(), bytes.end()); },
                      registry, {.library = "wheeltec-record 0.1.0", .chunk_size = 64});
  writer.write_message(status, 1'000'000'000, 1'000'000'000, text_bytes(R"({"control":{"sent":{"vx":0.0}}})"));
  writer.write_message(telemetry, 2'000'000'000, 2'000'000'000, text_bytes(R"({"seq":2,"time":2.0,"v":0.10})"));
  writer.write_message(telemetry, 1'500'000'000, 1'500'000'000, text_bytes(R"({"seq":1,"time":1.5})"));
  writer.write_message(odom, 1'500'000'000, 1'500'000'000, text_bytes(R"({"frame_id":"odom"})"));
  writer.write_message(events, 3'000'000'000, 3'000'000'000, text_bytes(odd_event));
  writer.write_metadata("wheeltec", {{"version", "0.1.0"}, {"triggers", R"([{"trigger":"mark","time":3.0}])"}});
  writer.finish();
  return file;
}

TEST(RecordMessages, EachListInLogTimeOrderWithTheFilesOwnJson) {
  const mcap::Bytes file = recorded();
  const auto answer = record_messages_json("20261127T153012Z-mark.mcap", file);
  ASSERT_TRUE(std::holds_alternative<std::string>(answer)) << std::get<UnreadableRecord>(answer).problem;
  const std::string& text = std::get<std::string>(answer);
  // The number as the file wrote it: not re-printed.
  EXPECT_NE(text.find(R"({"seq":2,"time":2.0,"v":0.10})"), std::string::npos) << text;
  const nlohmann::json json = nlohmann::json::parse(text);
  EXPECT_EQ(json["name"], "20261127T153012Z-mark.mcap");
  EXPECT_EQ(json["metadata"]["version"], "0.1.0");
  EXPECT_EQ(json["metadata"]["triggers"], R"([{"trigger":"mark","time":3.0}])");
  ASSERT_EQ(json["telemetry"].size(), 2u);
  EXPECT_EQ(json["telemetry"][0]["seq"], 1);
  EXPECT_EQ(json["telemetry"][1]["seq"], 2);
  EXPECT_EQ(json["status"].size(), 1u);
  EXPECT_EQ(json["events"], nlohmann::json::parse(R"([{"time":3.0,"event":"mark","client":2}])"));
  EXPECT_EQ(json.size(), 5u) << "only name, metadata, telemetry, status, events";
}

TEST(RecordMessages, WhatCannotBeReadIsNamed) {
  const auto problem = [](const mcap::Bytes& file) {
    const auto answer = record_messages_json("x.mcap", file);
    return std::holds_alternative<UnreadableRecord>(answer) ? std::get<UnreadableRecord>(answer).problem : "";
  };
  EXPECT_NE(problem(mcap::Bytes{}).find("not an MCAP file"), std::string::npos);
  mcap::Bytes file = recorded();
  mcap::Bytes cut(file.begin(), file.begin() + static_cast<std::ptrdiff_t>(file.size() / 2));
  EXPECT_NE(problem(cut).find("Data End"), std::string::npos) << problem(cut);
  mcap::Bytes damaged = file;
  damaged[damaged.size() / 3] ^= std::byte{0x10};
  EXPECT_FALSE(problem(damaged).empty());
  EXPECT_NE(problem(recorded("{\"event\": oops}")).find("message 1 on /events"), std::string::npos);
  EXPECT_EQ(record_error_json("x.mcap", "bad"), "{\"error\":\"bad\",\"name\":\"x.mcap\"}\n");
}

// The documented limit against the recorder's longest incident: 10 minutes at 20 Hz, with
// records, poses and transforms as wheeltec-record writes them and a status each second.
TEST(RecordMessages, ATenMinuteIncidentAt20HzFitsTheLimit) {
  mcap::Registry registry;
  const auto schema = registry.add_schema("wheeltec.Telemetry", "jsonschema", text_bytes("{}"));
  const auto telemetry = registry.add_channel(schema, "/telemetry", "json");
  const auto status = registry.add_channel(schema, "/status", "json");
  const auto odom = registry.add_channel(schema, "/odom", "json");
  const auto tf = registry.add_channel(schema, "/tf", "json");
  mcap::Bytes file;
  mcap::Writer writer([&file](mcap::ByteView bytes) { file.insert(file.end(), bytes.begin(), bytes.end()); },
                      registry, {.library = "wheeltec-record 0.1.0"});
  const std::string status_text = nlohmann::json{{"version", "0.1.0"}, {"bus", {{"state", "up"}}},
                                                 {"padding", std::string(1200, 'x')}}.dump();
  for (int i = 0; i < 20 * 600; ++i) {
    const double time = 1795552460.482002 + i * 0.05;
    const std::uint64_t ns = static_cast<std::uint64_t>(time * 1e9);
    const std::string record = fmt::format(
        R"({{"seq":{},"time":{:.6f},"stopped":false,"velocity":{{"vx":{:.3f},"vy":0.000,"wz":{:.3f}}},)"
        R"("accel":{{"x":{:.4f},"y":0.0006,"z":9.7984}},"gyro":{{"x":0.00000,"y":-0.00027,"z":{:.5f}}},)"
        R"("battery":{{"voltage":{:.3f},"low":false}},"odom":{{"x":{:.6f},"y":0.000024,"yaw":{:.6f}}},)"
        R"("orientation":{{"w":1.000000,"x":0.000046,"y":-0.000088,"z":0.000031,"roll":0.000091,)"
        R"("pitch":-0.000175,"yaw":{:.6f}}}}})",
        i + 1, time, 0.25 + (i % 7) * 0.001, (i % 13) * 0.01, (i % 11) * 0.001, (i % 17) * 0.0001,
        12.0 - i * 0.00001, i * 0.0125, i * 0.0001, i * 0.0001);
    writer.write_message(telemetry, ns, ns, text_bytes(record));
    const std::string pose = fmt::format(
        R"({{"timestamp":{{"sec":{},"nsec":{}}},"frame_id":"odom","pose":{{"position":{{"x":{:.6f},"y":0.000024,)"
        R"("z":0}},"orientation":{{"x":0,"y":0,"z":{:.6f},"w":1}}}}}})",
        ns / 1000000000, ns % 1000000000, i * 0.0125, i * 0.00005);
    writer.write_message(odom, ns, ns, text_bytes(pose));
    writer.write_message(tf, ns, ns, text_bytes(pose));
    if (i % 20 == 0) writer.write_message(status, ns, ns, text_bytes(status_text));
  }
  writer.finish();
  const auto started = std::chrono::steady_clock::now();
  const auto answer = record_messages_json("20261127T153012Z-mark.mcap", file);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  ASSERT_TRUE(std::holds_alternative<std::string>(answer));
  std::printf("[ figure ] 10 min at 20 Hz: file %.2f MB, messages JSON %.2f MB, read in %.0f ms\n",
              file.size() / 1e6, std::get<std::string>(answer).size() / 1e6, seconds * 1e3);
  EXPECT_LT(file.size(), kMaxMessagesFileBytes / 8) << "the limit leaves room for far more than this";
}

}  // namespace
}  // namespace wheeltec::web
