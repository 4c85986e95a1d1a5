#pragma once

#include <optional>
#include <string>

#include "wheeltec/emergency_stop.hpp"

#include "control_ports.hpp"

namespace wheeltec::daemon {

// safety.state_file (spec section 12): the latch written atomically (a temporary file beside
// it, fsync, rename, the directory fsynced) and read at start. Without a path it keeps nothing.
class SafetyStateFile : public LatchStore {
 public:
  explicit SafetyStateFile(std::optional<std::string> path) : path_(std::move(path)) {}

  // What the file says at start: not latched when there is none; latched as it was; and
  // latched, source client, when it exists but is not one this daemon wrote (logged).
  SafetyState load(RealtimeNanos now) const;
  bool save(const SafetyState& state) override;

  // At start: the directory exists and takes a new file; else ConfigError naming the path.
  static void check_writable(const std::string& path);

 private:
  std::optional<std::string> path_;
};

}  // namespace wheeltec::daemon
