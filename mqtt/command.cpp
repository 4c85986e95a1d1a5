#include "command.hpp"

#include <cmath>

namespace wheeltec::mqtt {
namespace {

// Deeper than any command: refused before parsing, so that a payload of 64 Ki brackets
// costs nothing.
constexpr int kMaxDepth = 8;

bool nested_too_deep(std::string_view text) {
  int depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxDepth) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

CommandRefusal refuse(int code, std::string message, Json id = nullptr) {
  return CommandRefusal{code, std::move(message), std::move(id)};
}

}  // namespace

ParsedCommand parse_command(Command command, std::string_view payload) {
  CommandRequest request{command, nullptr, nullptr, std::nullopt};
  const bool lenient = command == Command::stop;
  if (payload.size() > kMaxCommandBytes) {
    if (lenient) return request;
    return refuse(kInvalidRequest, "payload larger than " + std::to_string(kMaxCommandBytes) + " bytes");
  }
  Json document = Json::object();
  if (!payload.empty()) {
    if (nested_too_deep(payload)) {
      if (lenient) return request;
      return refuse(kInvalidRequest, "payload nested deeper than " + std::to_string(kMaxDepth) + " levels");
    }
    document = Json::parse(payload, nullptr, /*allow_exceptions=*/false);
    if (document.is_discarded()) {
      if (lenient) return request;
      return refuse(kParseError, "payload is not JSON");
    }
    if (!document.is_object()) {
      if (lenient) return request;
      return refuse(kInvalidRequest, std::string("payload must be a JSON object, got ") + document.type_name());
    }
  }

  if (const auto id = document.find("id"); id != document.end()) {
    if (!id->is_string() && !id->is_number()) {
      if (!lenient) return refuse(kInvalidRequest, "id must be a string or a number");
    } else {
      request.id = *id;
    }
  }
  Json params = Json::object();
  for (const auto& [key, value] : document.items()) {
    if (key == "id") continue;
    if (key == "operator") {
      if (!value.is_string() || value.get_ref<const std::string&>().empty() ||
          value.get_ref<const std::string&>().size() > kMaxOperatorNameBytes) {
        if (lenient) continue;
        return refuse(kInvalidParams, "operator must be a string of 1 to " + std::to_string(kMaxOperatorNameBytes) +
                                          " bytes",
                      request.id);
      }
      request.operator_name = value.get<std::string>();
      continue;
    }
    if (lenient) continue;
    const bool velocity = command == Command::drive && (key == "vx" || key == "vy" || key == "wz");
    if (!velocity) return refuse(kInvalidParams, "unknown param " + key, request.id);
    if (!value.is_number() || !std::isfinite(value.get<double>())) {
      return refuse(kInvalidParams, key + " must be a finite number", request.id);
    }
    params[key] = value.get<double>();
  }
  if (command == Command::drive) request.params = std::move(params);
  return request;
}

Json error_object(int code, std::string_view message) { return Json{{"code", code}, {"message", message}}; }

Json result_reply(Command command, const Json& id, const Json& result) {
  return Json{{"jsonrpc", "2.0"}, {"id", id}, {"command", command_name(command)}, {"result", result}};
}

Json error_reply(Command command, const Json& id, const Json& error) {
  return Json{{"jsonrpc", "2.0"}, {"id", id}, {"command", command_name(command)}, {"error", error}};
}

}  // namespace wheeltec::mqtt
