#include "drive_blocks.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include <fmt/format.h>

#include "bench_clock.hpp"
#include "bench_figures.hpp"
#include "latency_stats.hpp"

namespace bench {

void DriveSeries::add(int mm_per_s, std::int64_t sent_ns, std::optional<std::int64_t> frame_ns) {
  if (!frame_ns) {
    ++missed;
    return;
  }
  latency_us.push_back(static_cast<double>(*frame_ns - sent_ns) / 1e3);
  timed.push_back({mm_per_s, sent_ns, *frame_ns});
}

double DriveSeries::p50_us() const { return summarize(latency_us).p50_us; }

nlohmann::json DriveSeries::to_json() const {
  nlohmann::json j = summarize(latency_us).to_json();
  j["missed"] = missed;
  j["samples_us"] = samples_json(latency_us);
  return j;
}

int next_target(int& mm_per_s, int base) { return mm_per_s = base + (mm_per_s - base + 1) % 100; }

namespace {

void paced(int count, double interval_ms, const std::function<void()>& one) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < count; ++i) {
    std::this_thread::sleep_until(start + std::chrono::microseconds(static_cast<long long>(i * interval_ms * 1000)));
    one();
  }
}

void run_block(DrivePath& path, int count, bool counted, double interval_ms) {
  path.open();
  const double cpu0 = path.cpu_of >= 0 ? cpu_s(path.cpu_of) : 0.0;
  paced(count, interval_ms, [&] { path.drive(counted); });
  if (counted && path.cpu_of >= 0) path.cpu_s += cpu_s(path.cpu_of) - cpu0;
  path.stop();
}

}  // namespace

void drive_in_alternating_blocks(std::vector<DrivePath>& paths, const DriveSchedule& schedule) {
  for (auto& path : paths) {
    if (path.warm_up) run_block(path, 3, false, schedule.interval_ms);
  }
  for (int done = 0; done < schedule.drives; done += schedule.block) {
    const int n = std::min(schedule.block, schedule.drives - done);
    for (auto& path : paths) run_block(path, n, true, schedule.interval_ms);
  }
}

void keep_error(const std::string& reply, const std::string& what, std::vector<std::string>& first_errors) {
  if (reply.find("\"result\"") == std::string::npos && first_errors.size() < 5) first_errors.push_back(what + ": " + reply);
}

DrivePath SocketDrives::path(DriveSeries& series) {
  DrivePath path;
  path.open = [this] { client_ = std::make_unique<LineClient>(socket_); };
  path.drive = [this, &series](bool counted) {
    const int mm = next_target(mm_per_s_, 100);
    frames_.drain();
    const std::string line = fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"drive","params":{{"vx":{:.3f}}}}})",
                                         ++id_, mm / 1000.0);
    const std::int64_t sent = realtime_ns();
    client_->send_line(line);
    const auto frame = frames_.first_with(mm);
    keep_error(client_->read_line(2000), "direct drive", first_errors_);
    if (counted) series.add(mm, sent, frame);
  };
  path.stop = [this] {
    stop_on(*client_);
    client_.reset();
  };
  return path;
}

void SocketDrives::stop_on(LineClient& client) {
  client.send_line(fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"stop"}})", ++id_));
  keep_error(client.read_line(2000), "stop", first_errors_);
}

}  // namespace bench
