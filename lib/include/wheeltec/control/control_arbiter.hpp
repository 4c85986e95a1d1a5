#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

using ClientId = std::uint64_t;

// Who holds control and what the target is, with the deadman rule of the contract:
// the owner keeps control while it drives at least every command_timeout; when that
// lapses, it disconnects or anyone stops, the target is zero and control is released.
class ControlArbiter {
 public:
  explicit ControlArbiter(std::chrono::nanoseconds command_timeout);

  // False when another client holds control (nothing changes then).
  bool try_drive(ClientId client, const Velocity& target, MonotonicNanos now);

  // Zero target, no owner.
  void stop();

  // Called when a client goes away; true if it held control (target is now zero).
  bool release(ClientId client);

  // True if the owner's deadline passed at `now` (target is now zero, no owner).
  bool expire(MonotonicNanos now);

  void set_command_timeout(std::chrono::nanoseconds timeout) { timeout_ = timeout; }
  std::chrono::nanoseconds command_timeout() const { return timeout_; }
  std::optional<ClientId> owner() const { return owner_; }
  const Velocity& target() const { return target_; }
  // When the owner loses control unless it drives again; empty without an owner.
  std::optional<MonotonicNanos> deadline() const { return deadline_; }
  // The owner's last accepted drive; empty without an owner.
  std::optional<MonotonicNanos> last_drive() const { return last_drive_; }

 private:
  std::chrono::nanoseconds timeout_;
  std::optional<ClientId> owner_;
  Velocity target_;
  std::optional<MonotonicNanos> deadline_;
  std::optional<MonotonicNanos> last_drive_;
};

}  // namespace wheeltec
