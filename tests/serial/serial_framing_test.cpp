// What the daemon makes of the controller's byte stream (spec section 8, Telemetry): frames
// found by content, junk and bad frames passed over and counted in stats.serial, and a
// mebibyte of noise survived.

#include <gtest/gtest.h>

#include <random>
#include <thread>

#include "serial_daemon.hpp"
#include "wheeltec/frames/serial_frame.hpp"

namespace serial_tests {
namespace {

using SerialFraming = SerialTest;

// The serial counters of `stats`, as numbers (0 when absent, so that a missing key fails the
// comparison with a readable message rather than an exception).
struct SerialCounters {
  std::uint64_t bytes_received = 0;
  std::uint64_t bytes_skipped = 0;
  std::uint64_t bad_checksum = 0;
  std::uint64_t bad_tail = 0;
  std::uint64_t reopens = 0;
};

SerialCounters serial_counters(RpcConnection& client, Json* stats_out = nullptr) {
  const Json stats = client.call("stats");
  if (stats_out != nullptr) *stats_out = stats;
  SerialCounters c;
  const Json& serial = stats.contains("serial") ? stats["serial"] : Json::object();
  const auto number = [](const Json& object, const char* key) -> std::uint64_t {
    return object.is_object() && object.contains(key) && object[key].is_number_unsigned() ? object[key].get<std::uint64_t>()
                                                                                          : 0;
  };
  c.bytes_received = number(serial, "bytes_received");
  c.bytes_skipped = number(serial, "bytes_skipped");
  c.reopens = number(serial, "reopens");
  const Json& rejected = serial.contains("frames_rejected") ? serial["frames_rejected"] : Json::object();
  c.bad_checksum = number(rejected, "bad_checksum");
  c.bad_tail = number(rejected, "bad_tail");
  return c;
}

// Telemetry notifications until `count` arrived or `timeout` passed; then `linger` more to
// catch any that should not be there.
std::vector<Json> collect_records(RpcConnection& client, std::size_t count, std::chrono::milliseconds timeout,
                                  std::chrono::milliseconds linger = 300ms) {
  std::vector<Json> records;
  const auto deadline = SteadyClock::now() + timeout;
  while (records.size() < count && SteadyClock::now() < deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
    if (auto n = client.wait_notification("telemetry", left)) records.push_back((*n)["params"]);
  }
  while (auto n = client.wait_notification("telemetry", linger)) records.push_back((*n)["params"]);
  return records;
}

std::vector<int> vx_mm_s(const std::vector<Json>& records) {
  std::vector<int> out;
  for (const auto& r : records) out.push_back(static_cast<int>(std::lround(r["velocity"]["vx"].get<double>() * 1000)));
  return out;
}

TEST_F(SerialFraming, GoodRecordsThroughJunkStrayHeaderDribbleBadBccBadTail) {
  SerialDaemon& daemon = start_daemon_up();
  auto client = daemon.connect();
  ASSERT_EQ(client.call("subscribe", {{"topics", {"telemetry"}}})["topics"], Json({"telemetry"}));
  const SerialCounters before = serial_counters(client);

  // Good records carry vx 101..105 mm/s; the bad ones 901 and 902 (never to be seen).
  const Bytes junk{0x00, 0x11, 0x7D, 0x7F, 0xFF, 0x13, 0x0D};  // no 0x7B, no 0x7C
  Bytes bad_bcc = record_bytes(resting_record(901));
  bad_bcc[22] ^= 0x01;
  ASSERT_NE(bad_bcc[22], 0x7B);
  Bytes bad_tail = record_bytes(resting_record(902));
  bad_tail[23] = 0x7E;
  for (std::size_t i = 1; i < 23; ++i) {
    ASSERT_NE(bad_bcc[i], 0x7B);  // no header inside the bad frames: the counts below are exact
    ASSERT_NE(bad_bcc[i], 0x7C);
    ASSERT_NE(bad_tail[i], 0x7B);
    ASSERT_NE(bad_tail[i], 0x7C);
  }

  std::uint64_t written = 0;
  const auto send = [&](const Bytes& bytes) {
    fake_->write(bytes);
    written += bytes.size();
    std::this_thread::sleep_for(30ms);
  };
  // 1. junk, then a record
  send(junk);
  send(record_bytes(resting_record(101)));
  // 2. a stray 0x7B right before a record
  Bytes stray{0x7B};
  const Bytes r102 = record_bytes(resting_record(102));
  stray.insert(stray.end(), r102.begin(), r102.end());
  send(stray);
  // 3. a record dribbled one byte per write; its time is when its last byte was read
  const Bytes r103 = record_bytes(resting_record(103));
  fake_->dribble(Bytes(r103.begin(), r103.end() - 1), 5ms);
  const double before_last_byte = wall_seconds_now();
  fake_->write(Bytes{r103.back()});
  written += r103.size();
  std::this_thread::sleep_for(30ms);
  // 4. a record with a bad BCC, then a good one
  send(bad_bcc);
  send(record_bytes(resting_record(104)));
  // 5. a record with a bad tail, then a good one
  send(bad_tail);
  send(record_bytes(resting_record(105)));

  const std::vector<Json> records = collect_records(client, 5, 3s);
  EXPECT_EQ(vx_mm_s(records), (std::vector<int>{101, 102, 103, 104, 105}))
      << "every good record once, in order, and none of the bad ones\n" << logs();
  if (records.size() >= 3) {
    const double time = records[2]["time"].get<double>();
    EXPECT_GE(time, before_last_byte - 0.002)
        << "the dribbled record's time must be when its last byte was read (it took 115 ms to arrive)";
    EXPECT_LT(time, before_last_byte + 1.0);
  }
  const Json latest = client.call("telemetry");
  EXPECT_EQ(std::lround(latest["velocity"]["vx"].get<double>() * 1000), 105) << latest.dump();

  Json stats;
  const SerialCounters after = serial_counters(client, &stats);
  EXPECT_EQ(after.bytes_received - before.bytes_received, written) << stats.dump();
  // Skipped: the 7 junk bytes, the stray 0x7B, the 24 bytes of each bad frame.
  EXPECT_EQ(after.bytes_skipped - before.bytes_skipped, 7u + 1u + 24u + 24u) << stats.dump();
  EXPECT_EQ(after.bad_checksum - before.bad_checksum, 1u) << stats.dump();
  // Bad tail: the record with the wrong tail, and the stray 0x7B's 24-byte window (its byte 23
  // was the following record's BCC, not 0x7D).
  EXPECT_EQ(after.bad_tail - before.bad_tail, 2u) << stats.dump();
  // docs/api.md: reopens counts the opens after a loss, not the first one.
  EXPECT_EQ(after.reopens, 0u) << "the port was opened once and never lost: " << stats.dump();
  EXPECT_EQ(daemon.connect().call("status")["bus"]["state"], "up");
}

TEST_F(SerialFraming, ChargeFrameFeedsTheDockNotTheTelemetry) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_up();
  auto client = daemon.connect();
  ASSERT_TRUE(wait_for_status(client, [](const Json& s) { return s["chassis"]["online"] == true; }, 2s)) << logs();
  EXPECT_EQ(client.call("status")["dock"], Json({{"present", false}}));
  const auto records_before = client.call("stats")["records_accepted"];

  // 7C, current 0, IR receivers 0 and 2, charging, state 0, BCC 0x78, 7F; sent twice, as
  // the C50X firmware does on USART3.
  const Bytes charging{0x7C, 0x00, 0x00, 0x05, 0x01, 0x00, 0x78, 0x7F};
  Bytes twice = charging;
  twice.insert(twice.end(), charging.begin(), charging.end());
  fake_->write(twice);
  Json last;
  const auto present = wait_for_status(client, [](const Json& s) { return s["dock"]["present"] == true; }, 1s, &last);
  ASSERT_TRUE(present) << "a charge frame must make the dock present: " << last.dump();
  EXPECT_EQ((*present)["dock"], Json({{"present", true}, {"charging", true}, {"ir", {true, false, true, false}}}));

  // Not charging, IR receiver 3 only: 7C 00 00 08 00 00 BCC 7F, BCC = 7C ^ 08 = 0x74.
  fake_->write(Bytes{0x7C, 0x00, 0x00, 0x08, 0x00, 0x00, 0x74, 0x7F});
  const auto idle = wait_for_status(client, [](const Json& s) { return s["dock"]["charging"] == false; }, 1s, &last);
  ASSERT_TRUE(idle) << last.dump();
  EXPECT_EQ((*idle)["dock"], Json({{"present", true}, {"charging", false}, {"ir", {false, false, false, true}}}));

  // A charge frame with a bad BCC changes nothing.
  fake_->write(Bytes{0x7C, 0x00, 0x00, 0x05, 0x01, 0x00, 0x79, 0x7F});
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(client.call("status")["dock"]["charging"], false);
  const Json stats = client.call("stats");
  EXPECT_GE(stats["serial"]["frames_rejected"]["bad_checksum"], 1) << stats.dump();
  // The records kept flowing at 20 Hz between the charge frames.
  EXPECT_GT(stats["records_accepted"].get<std::uint64_t>(), records_before.get<std::uint64_t>());
  EXPECT_EQ(client.call("status")["chassis"]["online"], true);
}

TEST_F(SerialFraming, StatsSerialHasTheCounters) {
  SerialDaemon& daemon = start_daemon_up();
  auto client = daemon.connect();
  const Json stats = client.call("stats");
  ASSERT_TRUE(stats.contains("serial")) << stats.dump();
  const Json& serial = stats["serial"];
  for (const char* key : {"bytes_received", "bytes_skipped", "reopens"}) {
    EXPECT_TRUE(serial.contains(key) && serial[key].is_number_unsigned()) << key << " in " << serial.dump();
  }
  ASSERT_TRUE(serial.contains("frames_rejected") && serial["frames_rejected"].is_object()) << serial.dump();
  for (const char* key : {"bad_checksum", "bad_tail"}) {
    EXPECT_TRUE(serial["frames_rejected"].contains(key) && serial["frames_rejected"][key].is_number_unsigned())
        << key << " in " << serial.dump();
  }
}

TEST_F(SerialFraming, MebibyteOfRandomBytesThenGoodRecords) {
  SerialDaemon& daemon = start_daemon_up();
  auto client = daemon.connect();
  const SerialCounters before = serial_counters(client);

  std::mt19937 random(8);
  std::uniform_int_distribution<int> byte(0, 255);
  Bytes junk(1 << 20);
  for (auto& b : junk) b = static_cast<std::uint8_t>(byte(random));
  Bytes good;
  for (int i = 0; i < 20; ++i) {
    const Bytes r = record_bytes(resting_record(static_cast<std::int16_t>(201 + i)));
    good.insert(good.end(), r.begin(), r.end());
  }
  // What the sliding rule makes of it (FrameFinder is unit-tested against a plain reference).
  wheeltec::serial::FrameFinder oracle;
  std::vector<int> oracle_vx;
  const auto on_found = [&](const wheeltec::serial::FoundFrame& frame) {
    if (const auto* record = std::get_if<wheeltec::RecordBytes>(&frame)) oracle_vx.push_back(wheeltec::decode_raw(*record).vx);
  };
  oracle.feed(junk, on_found);
  const std::size_t junk_records = oracle_vx.size();
  oracle.feed(good, on_found);
  ASSERT_GE(oracle_vx.size(), junk_records + 20);
  const std::vector<int> expected_tail(oracle_vx.end() - 20, oracle_vx.end());
  ASSERT_EQ(expected_tail.front(), 201) << "this seed's junk swallows a good record; pick another seed";

  const auto started = SteadyClock::now();
  for (std::size_t at = 0; at < junk.size(); at += 4096) {
    fake_->write(Bytes(junk.begin() + static_cast<std::ptrdiff_t>(at), junk.begin() + static_cast<std::ptrdiff_t>(at + 4096)));
    if (at == junk.size() / 2) {
      // The daemon answers in the middle of the flood.
      const Json status = client.call("status", nullptr, 2s);
      EXPECT_EQ(status["bus"]["state"], "up") << status.dump();
    }
  }
  std::printf("[ figure ] 1 MiB of random bytes taken by the daemon in %.2f s\n",
              seconds_between(started, SteadyClock::now()));
  ASSERT_TRUE(daemon.process().running()) << logs();
  const Json status = client.call("status", nullptr, 2s);
  EXPECT_EQ(status["bus"]["state"], "up") << status.dump();

  ASSERT_EQ(client.call("subscribe", {{"topics", {"telemetry"}}})["topics"], Json({"telemetry"}));
  for (std::size_t at = 0; at < good.size(); at += 24) {
    fake_->write(Bytes(good.begin() + static_cast<std::ptrdiff_t>(at), good.begin() + static_cast<std::ptrdiff_t>(at + 24)));
    std::this_thread::sleep_for(10ms);
  }
  const std::vector<Json> records = collect_records(client, 20, 5s);
  std::vector<int> seen = vx_mm_s(records);
  if (seen.size() > 20) seen.erase(seen.begin(), seen.end() - 20);
  EXPECT_EQ(seen, expected_tail) << "the good records after the noise\n" << logs();

  // Every byte read, the noise passed over as the sliding rule says.
  SerialCounters after = serial_counters(client);
  for (const auto deadline = SteadyClock::now() + 5s;
       after.bytes_received - before.bytes_received < junk.size() + good.size() && SteadyClock::now() < deadline;) {
    std::this_thread::sleep_for(20ms);
    after = serial_counters(client);
  }
  const auto& expected = oracle.counters();
  EXPECT_EQ(after.bytes_received - before.bytes_received, junk.size() + good.size());
  EXPECT_EQ(after.bytes_skipped - before.bytes_skipped, expected.bytes_skipped);
  EXPECT_EQ(after.bad_checksum - before.bad_checksum, expected.bad_checksum);
  EXPECT_EQ(after.bad_tail - before.bad_tail, expected.bad_tail);
  std::printf("[ figure ] noise: %llu bytes skipped, %llu bad checksum, %llu bad tail, %zu records by chance\n",
              static_cast<unsigned long long>(expected.bytes_skipped),
              static_cast<unsigned long long>(expected.bad_checksum), static_cast<unsigned long long>(expected.bad_tail),
              junk_records);
  EXPECT_TRUE(daemon.process().running()) << logs();
}

}  // namespace
}  // namespace serial_tests
