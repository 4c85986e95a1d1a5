#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>

namespace integration {

// How a process is scheduled, as a systemd unit would set it: the normal policy at a nice
// value (Nice=), or a real-time policy at a priority (CPUSchedulingPolicy=rr|fifo,
// CPUSchedulingPriority=).
struct Scheduling {
  enum Policy { normal, round_robin, fifo } policy = normal;
  int value = 0;  // the nice value for `normal`, else the real-time priority (1-99)

  // "nice:N", "rr:N" or "fifo:N"; throws std::invalid_argument naming what is wrong.
  static Scheduling parse(const std::string& text);
  std::string describe() const;
};

// The next priority above `scheduling`: one nice value lower (at most -20), or one real-time
// priority higher (at most 99) in the same policy.
Scheduling one_step_ahead(const Scheduling& scheduling);

// The scheduling a systemd service unit gives its process: CPUSchedulingPolicy=rr|fifo with
// CPUSchedulingPriority=, else Nice=; empty when the unit sets neither. Throws
// std::runtime_error when the file cannot be read or a value is not one of these.
std::optional<Scheduling> scheduling_of_unit(const std::filesystem::path& unit);

// Applies `scheduling` to every thread of process `pid` (needs root for a negative nice
// value or a real-time policy); throws std::runtime_error naming the thread that refused.
void apply_to_process(const Scheduling& scheduling, pid_t pid);
// Applies `scheduling` to the calling thread only.
void apply_to_this_thread(const Scheduling& scheduling);

}  // namespace integration
