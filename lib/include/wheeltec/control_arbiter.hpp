#pragma once

#include <cstdint>
#include <optional>

#include "wheeltec/types.hpp"

namespace wheeltec {

using ClientId = std::uint64_t;

// Who holds control and what the target is, with the deadman rule of the contract:
// the owner keeps control while it drives at least every command_timeout; when that
// lapses, it disconnects or anyone stops, the target is zero and control is released.
// Times are from a steady clock.
class ControlArbiter {
 public:
  explicit ControlArbiter(Nanos command_timeout);

  // False when another client holds control (nothing changes then).
  bool try_drive(ClientId client, const Velocity& target, Nanos now);

  // Zero target, no owner.
  void stop();

  // Called when a client goes away; true if it held control (target is now zero).
  bool release(ClientId client);

  // True if the owner's deadline passed at `now` (target is now zero, no owner).
  bool expire(Nanos now);

  void set_command_timeout(Nanos timeout) { timeout_ = timeout; }
  Nanos command_timeout() const { return timeout_; }
  std::optional<ClientId> owner() const { return owner_; }
  const Velocity& target() const { return target_; }
  // When the owner loses control unless it drives again; empty without an owner.
  std::optional<Nanos> deadline() const { return deadline_; }

 private:
  Nanos timeout_;
  std::optional<ClientId> owner_;
  Velocity target_;
  std::optional<Nanos> deadline_;
};

}  // namespace wheeltec
