#pragma once

// Why the link to the controller is down and when to try it again, for the CAN socket and
// the serial port alike (cannelloni's way: a fault is a state to report and recover from).
// Pure: the adapters tell it what happened and arm their retry timer with what it answers.

#include <array>
#include <chrono>
#include <optional>
#include <span>
#include <string_view>

#include "wheeltec/backoff.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

enum class LinkDownCause {
  absent,       // no such interface or device
  not_up,       // the CAN interface exists but is down
  busy,         // the serial device is held by another program
  open_failed,  // it exists but cannot be opened or set up (permissions, not a serial port, ...)
  unplugged,    // the serial adapter went away under an open port (end of file, EIO)
  io_error,     // the socket or port failed otherwise
};

inline constexpr std::array<EnumName<LinkDownCause>, 6> kLinkDownCauseNames{{
    {LinkDownCause::absent, "absent"},
    {LinkDownCause::not_up, "not-up"},
    {LinkDownCause::busy, "busy"},
    {LinkDownCause::open_failed, "open-failed"},
    {LinkDownCause::unplugged, "unplugged"},
    {LinkDownCause::io_error, "io-error"},
}};
constexpr std::span<const EnumName<LinkDownCause>> name_table(LinkDownCause) { return kLinkDownCauseNames; }
std::string_view to_string(LinkDownCause cause);

// Retries from `first` on, doubling up to `max` (first == max: a fixed interval).
struct RetryPolicy {
  std::chrono::milliseconds first{500};
  std::chrono::milliseconds max{5000};
};

class LinkRecovery {
 public:
  explicit LinkRecovery(RetryPolicy policy) : policy_(policy), retries_(policy.first, policy.max) {}

  // Down, or an open that failed, for `cause`: true if that is news (a different cause than
  // the one known), worth a warning; a repeat is worth a debug line.
  bool down(LinkDownCause cause);
  // The delay before the next retry; each call doubles the one after, up to the policy's max.
  std::chrono::milliseconds next_retry() { return retries_.next(); }
  // Open again: no cause, the backoff starts over; what the cause was, if any.
  std::optional<LinkDownCause> opened();

  std::optional<LinkDownCause> cause() const { return cause_; }
  const RetryPolicy& policy() const { return policy_; }

 private:
  RetryPolicy policy_;
  Backoff retries_;
  std::optional<LinkDownCause> cause_;
};

}  // namespace wheeltec
