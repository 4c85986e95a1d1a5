#pragma once

// A remote command as it arrives on PREFIX/ROBOT/cmd/NAME, turned into the daemon's
// request or refused; and the reply that goes back. Pure: no I/O.
//
// Payload: empty, or a JSON object. `drive` takes "vx", "vy", "wz" (numbers, absent = 0);
// every command may carry "id" (a string or number, echoed in the reply: the correlation
// of MQTT 3.1.1 clients) and "operator" (who sends it, see operator_sessions.hpp). `estop`
// takes "reason" (a string). `stop` and `estop` are never refused, whatever their payload:
// what cannot be read is left out, and an estop's reason longer than the daemon takes is
// cut, so that a badly written emergency stop still stops.

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "wheeltec/error_codes.hpp"

#include "topics.hpp"

namespace wheeltec::mqtt {

using Json = nlohmann::ordered_json;

inline constexpr std::size_t kMaxCommandBytes = 64 * 1024;  // the daemon's line limit
inline constexpr std::size_t kMaxOperatorNameBytes = 128;
// The daemon takes a reason of at most 200 characters; 200 bytes are that many at most.
inline constexpr std::size_t kMaxEstopReasonBytes = 200;

// The JSON-RPC error codes the bridge itself answers with are wheeltecd's list's
// (kParseError, kInvalidRequest, kInvalidParams, kTooManyOperators, kDaemonUnreachable).
using namespace wheeltec::error_codes;

struct CommandRequest {
  Command command;
  Json params;  // null: none
  Json id;      // null: none given
  std::optional<std::string> operator_name;
};

struct CommandRefusal {
  int code;
  std::string message;
  Json id;  // when it could be read
};

using ParsedCommand = std::variant<CommandRequest, CommandRefusal>;

ParsedCommand parse_command(Command command, std::string_view payload);

// {"jsonrpc":"2.0","id":ID,"command":NAME,"result":RESULT} and the same with "error".
Json result_reply(Command command, const Json& id, const Json& result);
Json error_reply(Command command, const Json& id, const Json& error);
Json error_object(int code, std::string_view message);

}  // namespace wheeltec::mqtt
