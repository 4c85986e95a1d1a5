#pragma once

// The drives of a bridge benchmark: drives over each bridge and on wheeltecd's socket, in
// alternating blocks so that every path sees the same load on the host, each timed to the
// first command frame carrying its velocity.

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "command_frames.hpp"
#include "subscriber_set.hpp"

namespace bench {

struct DriveSeries {
  struct Timed {
    int mm_per_s;
    std::int64_t sent_ns, frame_ns;
  };
  std::vector<double> latency_us;
  std::vector<Timed> timed;  // each counted drive that reached the link
  int missed = 0;            // no frame with the velocity within 1 s
  void add(int mm_per_s, std::int64_t sent_ns, std::optional<std::int64_t> frame_ns);
  double p50_us() const;
  nlohmann::json to_json() const;
};

// The next of the targets base .. base + 99 mm/s: each drive a new one, so that the daemon
// sends its frame at once.
int next_target(int& mm_per_s, int base);

struct DrivePath {
  std::function<void(bool counted)> drive;
  std::function<void()> stop;          // after each block: releases control
  std::function<void()> open = [] {};  // before each block
  bool warm_up = true;                 // 3 uncounted drives and a stop before the blocks
  pid_t cpu_of = -1;                   // given: that process' utime+stime over its drives, summed
  double cpu_s = 0;
};

struct DriveSchedule {
  int drives = 300;
  int block = 50;
  double interval_ms = 100.0;  // an operator's tool repeating its drive at 10 Hz
};

void drive_in_alternating_blocks(std::vector<DrivePath>& paths, const DriveSchedule& schedule);

// A JSON-RPC reply that is not a result, kept among the first five errors.
void keep_error(const std::string& reply, const std::string& what, std::vector<std::string>& first_errors);

// Drives written on wheeltecd's socket, on a connection of each block's own: closing it
// releases control.
class SocketDrives {
 public:
  SocketDrives(std::filesystem::path socket, CommandFrames& frames, std::vector<std::string>& first_errors)
      : socket_(std::move(socket)), frames_(frames), first_errors_(first_errors) {}
  DrivePath path(DriveSeries& series);
  // `stop` on another client (any client's stop releases control, a bridge's too).
  void stop_on(LineClient& client);

 private:
  std::filesystem::path socket_;
  CommandFrames& frames_;
  std::vector<std::string>& first_errors_;
  std::unique_ptr<LineClient> client_;
  int mm_per_s_ = 100;
  int id_ = 0;
};

}  // namespace bench
