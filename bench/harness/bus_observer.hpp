#pragma once

// A thread that watches the robots' buses and one robot's daemon directly:
//  - a raw CAN socket per interface, kernel filter 0x103, SO_TIMESTAMPNS: the kernel
//    receive time of every record's last frame, which is also the record's `time` in the
//    daemon's telemetry (truncated to the microsecond);
//  - optionally a client of one wheeltecd subscribed to telemetry, which keeps when each
//    record arrived there: the reference for what the daemon alone costs.

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "can_endpoint.hpp"
#include "stop_signal.hpp"
#include "subscriber_set.hpp"

namespace bench {

class BusObserver {
 public:
  BusObserver(const std::vector<std::string>& interfaces, const std::optional<std::filesystem::path>& daemon_socket);
  ~BusObserver();
  BusObserver(const BusObserver&) = delete;
  BusObserver& operator=(const BusObserver&) = delete;

  // Kernel receive times (CLOCK_REALTIME, ns) of the 0x103 frames seen on interface `index`.
  std::vector<std::int64_t> record_frames(std::size_t index) const;
  // For the daemon given: (record `time` in us, CLOCK_REALTIME ns when its notification was read).
  std::vector<std::pair<std::int64_t, std::int64_t>> direct_notifications() const;

 private:
  void run();
  void read_direct();

  std::vector<std::unique_ptr<CanEndpoint>> sockets_;
  std::unique_ptr<LineClient> direct_;
  std::string direct_buffer_;
  StopSignal stop_;
  mutable std::mutex mutex_;
  std::vector<std::vector<std::int64_t>> frames_;
  std::vector<std::pair<std::int64_t, std::int64_t>> direct_notifications_;
  std::thread thread_;
};

// A record's `time` member, as written in the JSON text, in microseconds (empty if absent).
std::optional<std::int64_t> record_time_us(const std::string& json_text);
// The `seq` member, likewise.
std::optional<std::int64_t> record_seq(const std::string& json_text);

}  // namespace bench
