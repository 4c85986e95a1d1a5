#pragma once

// One line from wheeltecd read without building a tree when it is a notification in the
// daemon's own layout, {"jsonrpc":"2.0","method":"NAME","params":PARAMS} (lib's
// telemetry_json writes telemetry that way): the method and the params as slices of the
// line, so that a program can forward the daemon's bytes. Pure: no I/O.

#include <string>
#include <string_view>
#include <variant>

namespace wheeltec::client {

// A notification in the daemon's layout; `params` is valid JSON (checked without a tree).
struct DaemonNotification {
  std::string_view method;
  std::string_view params;
};
// Not a notification in that layout (a reply, another key order or spacing): parse the
// line whole.
struct OtherLayout {};
// Starts as the daemon's notifications do but is not JSON.
struct MalformedLine {
  std::string reason;
};
using NotificationRead = std::variant<DaemonNotification, OtherLayout, MalformedLine>;

NotificationRead read_notification(std::string_view line);

}  // namespace wheeltec::client
