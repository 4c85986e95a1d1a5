#include "safety_request.hpp"

#include <fmt/format.h>

#include "wheeltec/error_codes.hpp"
#include "wheeltec/config/json_text.hpp"

namespace wheeltec::web {
namespace {

bool blank_text(std::string_view text) {
  return text.find_first_not_of(" \t\r\n") == std::string_view::npos;
}

}  // namespace

std::variant<Json, RequestProblem> estop_params(std::string_view body) {
  if (blank_text(body)) return Json::object();
  json_text::StrictRead read = json_text::read_strict(body, json_text::kMaxMessageDepth);
  if (read.refusal) {
    if (read.refusal->reason == json_text::Refusal::Reason::not_json) {
      return RequestProblem{fmt::format("the body is not JSON: {}", read.refusal->message)};
    }
    return RequestProblem{fmt::format("the body is refused: {}", read.refusal->message)};
  }
  const Json& document = read.document;
  if (!document.is_object()) return RequestProblem{"the body must be a JSON object: {\"reason\": \"...\"}, or empty"};
  const auto reason = document.find("reason");
  if (reason == document.end()) return Json::object();
  if (!reason->is_string()) return RequestProblem{"\"reason\" must be a string"};
  return Json{{"reason", *reason}};
}

unsigned http_status_of_rpc_error(int code) {
  switch (code) {
    case error_codes::kInvalidParams: return 400;
    case error_codes::kNotPermitted: return 403;
    case error_codes::kEmergencyStopLatched: return 409;
    case error_codes::kDaemonUnreachable: return 503;
    default: return 502;
  }
}

Json rpc_error_body(int code, std::string_view message) {
  return Json{{"code", code}, {"message", message}};
}

}  // namespace wheeltec::web
