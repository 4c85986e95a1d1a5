#include "command.hpp"

#include <cmath>

#include "wheeltec/drive_velocity.hpp"
#include "wheeltec/config/json_text.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec::mqtt {
namespace {

CommandRefusal refuse(int code, std::string message, Json id = nullptr) {
  return CommandRefusal{code, std::move(message), std::move(id)};
}

// `text` cut to at most `bytes` bytes, at a character boundary (text is valid UTF-8).
std::string utf8_prefix(const std::string& text, std::size_t bytes) {
  if (text.size() <= bytes) return text;
  std::size_t end = bytes;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  return text.substr(0, end);
}

}  // namespace

ParsedCommand parse_command(Command command, std::string_view payload) {
  CommandRequest request{command, nullptr, nullptr, std::nullopt};
  const bool lenient = command == Command::stop || command == Command::estop;
  if (payload.size() > kMaxCommandBytes) {
    if (lenient) return request;
    return refuse(kInvalidRequest, "payload larger than " + std::to_string(kMaxCommandBytes) + " bytes");
  }
  Json document = Json::object();
  if (!payload.empty()) {
    json_text::StrictRead read = json_text::read_strict(payload, json_text::kMaxMessageDepth);
    using Reason = json_text::Refusal::Reason;
    if (read.refusal && read.refusal->reason != Reason::duplicate_key) {
      if (lenient) return request;
      if (read.refusal->reason == Reason::not_json) {
        return refuse(kParseError, "payload is not JSON: " + read.refusal->message);
      }
      return refuse(kInvalidRequest, "payload " + read.refusal->message);
    }
    if (!read.document.is_object()) {
      if (lenient) return request;
      return refuse(kInvalidRequest, std::string("payload must be a JSON object, got ") + read.document.type_name());
    }
    // A command that says two things is not guessed at; a stop reads the last of them.
    if (read.refusal && !lenient) return refuse(kInvalidRequest, read.refusal->message);
    document = std::move(read.document);
  }

  if (const auto id = document.find("id"); id != document.end()) {
    if (!id->is_string() && !id->is_number()) {
      if (!lenient) return refuse(kInvalidRequest, "id must be a string or a number");
    } else {
      request.id = *id;
    }
  }
  Json params = Json::object();
  Velocity velocity;  // each member checked as it comes; params keeps them as given
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
    if (command == Command::estop && key == "reason") {
      if (value.is_string()) params["reason"] = utf8_prefix(value.get<std::string>(), kMaxEstopReasonBytes);
      continue;
    }
    if (lenient) continue;
    if (command != Command::drive) return refuse(kInvalidParams, "unknown param \"" + key + "\"", request.id);
    if (auto problem = read_drive_member(key, value, velocity)) return refuse(kInvalidParams, *problem, request.id);
    params[key] = value.get<double>();
  }
  if (command == Command::drive || (command == Command::estop && !params.empty())) request.params = std::move(params);
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
