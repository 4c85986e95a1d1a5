#include "gateway_latency.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "bench_clock.hpp"
#include "subscriber_set.hpp"

namespace bench {

wheeltec::RawTelemetry bench_record(int n) {
  wheeltec::RawTelemetry raw;
  raw.vx = static_cast<std::int16_t>(n % 500);
  raw.accel_z = 16400;
  raw.battery_mv = 22500;
  return raw;
}

wheeltec::TelemetryGroup bench_group(int n) { return wheeltec::make_telemetry_group(wheeltec::encode_record(bench_record(n))); }

void CommandLatency::append(const CommandLatency& other) {
  total.insert(total.end(), other.total.begin(), other.total.end());
  to_frame.insert(to_frame.end(), other.to_frame.begin(), other.to_frame.end());
  after_frame.insert(after_frame.end(), other.after_frame.begin(), other.after_frame.end());
}

nlohmann::json CommandLatency::to_json() const {
  nlohmann::json j = summarize(total).to_json();
  j["to_frame"] = summarize(to_frame).to_json();
  j["after_frame"] = summarize(after_frame).to_json();
  return j;
}

CommandLatency command_latency(const std::filesystem::path& socket, int commands, int base_mm_per_s,
                               const FrameWait& await_frame) {
  LineClient client(socket);
  CommandLatency result;
  result.total.reserve(commands);
  result.to_frame.reserve(commands);
  result.after_frame.reserve(commands);
  for (int i = 0; i < commands; ++i) {
    const int mm_per_s = base_mm_per_s + (i % 2) * 100;  // a changed target each time: one frame at once
    const std::string line = fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"drive","params":{{"vx":{}}}}})",
                                         i + 1, mm_per_s / 1000.0);
    const double start = now_us();
    client.send_line(line);
    const std::optional<double> frame_us = await_frame(mm_per_s);
    if (!frame_us) throw std::runtime_error("no command frame within 1 s after drive #" + std::to_string(i + 1));
    const double end = now_us();
    result.total.push_back(end - start);
    result.to_frame.push_back(*frame_us - start);
    result.after_frame.push_back(end - *frame_us);
    const std::string reply = client.read_line(1000);
    if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error("drive failed: " + reply);
  }
  client.send_line(R"({"jsonrpc":"2.0","id":0,"method":"stop"})");
  client.read_line(1000);
  return result;
}

TelemetryLatency telemetry_latency(const std::filesystem::path& socket, std::size_t subscribers, int records,
                                   const RecordSender& send_record) {
  SubscriberSet set(socket, subscribers);
  std::vector<std::size_t> lines(subscribers, 0);
  std::vector<double> samples;
  samples.reserve(subscribers * records);
  TelemetryLatency result;
  for (int r = 0; r < records; ++r) {
    const double start = send_record(r);
    std::size_t waiting = subscribers;
    std::vector<bool> got(subscribers, false);
    const double deadline = start + 1e6;
    while (waiting > 0 && now_us() < deadline) {
      for (std::size_t index : set.poll(100, lines)) {
        if (got[index]) continue;
        got[index] = true;
        --waiting;
        samples.push_back(now_us() - start);
      }
    }
    result.lost += waiting;
  }
  result.all = summarize(std::move(samples));
  return result;
}

}  // namespace bench
