#pragma once

#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "wheeltec/error_codes.hpp"
#include "wheeltec/types.hpp"

// JSON-RPC 2.0 framing for the daemon's line protocol (spec section 2, "JSON API").
namespace wheeltec::rpc {

inline constexpr std::size_t kMaxLineBytes = 64 * 1024;  // without the '\n'

using namespace wheeltec::error_codes;  // kParseError ... kChassisNotReady: one list for all

struct Request {
  nlohmann::json id;          // null when is_notification
  bool is_notification = false;
  std::string method;
  nlohmann::json params;      // object, array or null (absent)
};

struct Error {
  int code = kInternalError;
  std::string message;
  nlohmann::json id;          // null when the request's id could not be read
  nlohmann::json data = nullptr;  // the error object's "data" member; left out when null
};

// Parses one line (without '\n'). Errors: unparsable or invalid UTF-8 -> -32700;
// not an object, a batch, missing/wrong "jsonrpc", missing/non-string "method",
// id not a string/number/null, params not an object/array -> -32600.
std::variant<Request, Error> parse_request(std::string_view line);

// Serialised responses and notifications, each ending in '\n'.
std::string encode_result(const nlohmann::json& id, const nlohmann::json& result);
std::string encode_error(const Error& error);
std::string encode_notification(std::string_view method, const nlohmann::json& params);

// drive params {"vx","vy","wz"} (absent = 0). Errors (-32602, message names the param):
// params not an object, unknown key, non-numeric or non-finite value, vy != 0 on a
// chassis that cannot move sideways.
std::variant<Velocity, Error> parse_drive_params(const Request& request, ChassisType chassis);

// Methods that take no params accept absent, null, {} or []; anything else is -32602.
std::optional<Error> expect_no_params(const Request& request);

inline constexpr std::string_view kTopicTelemetry = "telemetry";
inline constexpr std::string_view kTopicStatus = "status";
inline constexpr std::string_view kTopicEvents = "events";  // protocol 4

// subscribe/unsubscribe params {"topics": [...]} with known topic names; -32602 otherwise.
std::variant<std::vector<std::string>, Error> parse_topics(const Request& request);

// A mark's text may have at most this many characters (Unicode code points, not bytes).
inline constexpr std::size_t kMaxMarkCharacters = 200;

// mark params {"text": "..."}: the text (a view into request.params). -32602 for params
// that are not an object, an unknown param, a missing text, one that is not a string or
// one longer than kMaxMarkCharacters.
std::variant<std::string_view, Error> parse_mark_params(const Request& request);

// An estop's reason may have at most this many characters, like a mark's text.
inline constexpr std::size_t kMaxEstopReasonCharacters = 200;

// estop params: absent, null, {} or {"reason": "..."} (a view into request.params; "" when
// none). -32602 for anything else: an unknown param, a reason that is not a string or one
// longer than kMaxEstopReasonCharacters.
std::variant<std::string_view, Error> parse_estop_params(const Request& request);

}  // namespace wheeltec::rpc
