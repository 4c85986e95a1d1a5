#include "wheeltec/control/control_arbiter.hpp"

namespace wheeltec {

ControlArbiter::ControlArbiter(std::chrono::nanoseconds command_timeout) : timeout_(command_timeout) {}

bool ControlArbiter::try_drive(ClientId client, const Velocity& target, MonotonicNanos now) {
  if (owner_ && *owner_ != client) return false;
  owner_ = client;
  target_ = target;
  last_drive_ = now;
  deadline_ = now + timeout_;
  return true;
}

void ControlArbiter::stop() {
  target_ = Velocity{};
  owner_.reset();
  deadline_.reset();
  last_drive_.reset();
}

bool ControlArbiter::release(ClientId client) {
  if (owner_ != client) return false;
  stop();
  return true;
}

bool ControlArbiter::expire(MonotonicNanos now) {
  if (!owner_ || now < *deadline_) return false;
  stop();
  return true;
}

}  // namespace wheeltec
