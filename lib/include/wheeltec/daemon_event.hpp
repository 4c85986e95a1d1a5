#pragma once

// The daemon's events (spec section 10, docs/api.md "Events"): what happened to the
// chassis' control and to the API's connections, for the `events` topic. One type per
// kind, carrying exactly that kind's keys, and the one encoding of them as JSON. Pure: the
// daemon stamps an event with its clock and hands it to the subscribers.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include "wheeltec/clocks.hpp"
#include "wheeltec/control_arbiter.hpp"
#include "wheeltec/emergency_stop.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

namespace events {

// The connecting process' credentials (SO_PEERCRED).
struct Peer {
  std::uint32_t uid = 0;
  std::uint32_t gid = 0;
  std::int32_t pid = 0;
};

struct Connected {
  std::optional<Peer> peer;  // empty when the kernel did not tell: uid, gid, pid null
};
struct Disconnected {};
// A drive accepted: it became the target (also when it repeats the target).
struct Drive {
  Velocity sent;  // as sent: clamped and in the firmware's steps, as the drive's result
  bool clamped = false;
};
// A drive, enable or disable answered with an error.
struct Refused {
  std::string_view method;
  int code = 0;
  std::string_view message;
};
struct Stop {};
// Control lapsed (no drive within command_timeout_s, or the owner left) while the target
// was not zero.
struct Deadman {
  std::chrono::nanoseconds after{};  // since the owner's last drive
};
struct Enable {};
struct Disable {};
struct Mark {
  std::string_view text;
};
// The emergency stop latched (protocol 5): by a client's estop (the event's client is the
// caller) or a hazard (the daemon's own).
struct Estop {
  LatchSource source = LatchSource::client;
  std::string_view reason;
};
// A client released the latch.
struct Release {};
// SIGHUP handled.
struct Reload {
  std::optional<std::string_view> error;  // why the new configuration was refused; empty: ok
};

}  // namespace events

// The text members (method, message, text, error) are views: an event is encoded where it
// is made, and does not outlive the call that publishes it.
using EventBody = std::variant<events::Connected, events::Disconnected, events::Drive, events::Refused, events::Stop,
                               events::Deadman, events::Enable, events::Disable, events::Mark, events::Reload,
                               events::Estop, events::Release>;

struct DaemonEvent {
  RealtimeNanos time{};            // the daemon's clock, since the epoch
  std::optional<ClientId> client;  // the connection it concerns (status' control.owner); empty: the daemon's own
  EventBody body;
};

// "connected", "disconnected", "drive", "refused", "stop", "deadman", "enable", "disable",
// "mark", "reload", "estop", "release".
std::string_view event_name(const EventBody& body);

// Appends the EVENT object (no newline): "time" (6 decimals), "event", "client" (null for
// the daemon's own), then the kind's own keys in the order of the contract's table
// (velocities and after_s with 3 decimals). Strings are JSON-escaped; bytes that are not
// UTF-8 become U+FFFD. Does not allocate when `out` has capacity.
void append_event_json(std::string& out, const DaemonEvent& event);

// Appends {"jsonrpc":"2.0","method":"event","params":EVENT} and '\n'.
void append_event_notification(std::string& out, const DaemonEvent& event);

}  // namespace wheeltec
