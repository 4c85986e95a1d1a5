#pragma once

// Where the benchmark sees a robot's daemon command its chassis: on the robot's CAN bus (a
// raw socket of 0x121 frames, timed by the kernel's receive timestamp), or on the serial line
// whose controller the benchmark plays (the pty's master, timed when the frame is read: a
// pty has no receive timestamp).

#include <cstdint>
#include <optional>
#include <string>

#include "can_endpoint.hpp"
#include "pty_endpoint.hpp"

namespace bench {

class CommandFrames {
 public:
  virtual ~CommandFrames() = default;
  // Discards the frames seen so far.
  virtual void drain() = 0;
  // When (CLOCK_REALTIME ns) the first command frame with vx = mm_per_s was seen, within timeout_ms.
  virtual std::optional<std::int64_t> first_with(int mm_per_s, int timeout_ms = 1000) = 0;
};

class CanCommandFrames : public CommandFrames {
 public:
  explicit CanCommandFrames(const std::string& interface) : control_(interface, {0x121}) {}
  void drain() override;
  std::optional<std::int64_t> first_with(int mm_per_s, int timeout_ms = 1000) override;

 private:
  CanEndpoint control_;
};

class PtyCommandFrames : public CommandFrames {
 public:
  explicit PtyCommandFrames(PtyEndpoint& line) : line_(line) {}
  void drain() override;
  std::optional<std::int64_t> first_with(int mm_per_s, int timeout_ms = 1000) override;

 private:
  PtyEndpoint& line_;
};

}  // namespace bench
