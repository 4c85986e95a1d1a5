#include "wheeltec/rpc.hpp"

#include "wheeltec/drive_velocity.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "wheeltec/json_text.hpp"

namespace wheeltec::rpc {
namespace {

// Unicode code points: the parser took only valid UTF-8, so every byte but a continuation
// byte starts a character.
std::size_t character_count(const std::string& value) {
  return static_cast<std::size_t>(
      std::count_if(value.begin(), value.end(), [](char byte) { return (static_cast<unsigned char>(byte) & 0xC0) != 0x80; }));
}

using json = nlohmann::json;

// nlohmann's parser is iterative, but copying, comparing and dumping a document recurse;
// deeper containers are dropped while parsing and the request is refused.
constexpr int kMaxDepth = 64;

std::string dump(const json& value) {
  return value.dump(-1, ' ', false, json::error_handler_t::replace);
}

using json_text::printable;

Error invalid_params(const Request& request, std::string message) {
  return Error{kInvalidParams, std::move(message), request.id};
}

std::variant<Request, Error> parse_object(json& document, const json_text::StrictRead& read) {
  Request request;
  // With "id" given twice, which one the client meant is unknown: answer with a null id.
  const bool id_ambiguous = read.findings.duplicate_depth == 1 && read.findings.duplicate_key == "id";
  if (auto id = document.find("id"); id != document.end() && !id_ambiguous) {
    const bool finite_number = id->is_number() && std::isfinite(id->get<double>());
    if (!id->is_string() && !finite_number && !id->is_null()) {
      return Error{kInvalidRequest, "\"id\" must be a string, a number or null", nullptr};
    }
    request.id = std::move(*id);
  } else {
    request.is_notification = true;
  }
  auto fail = [&](std::string message) { return Error{kInvalidRequest, std::move(message), request.id}; };

  if (read.refusal) {
    const bool too_deep = read.refusal->reason == json_text::Refusal::Reason::too_deep;
    return fail(too_deep ? "request " + read.refusal->message : read.refusal->message);
  }

  const auto jsonrpc = document.find("jsonrpc");
  if (jsonrpc == document.end()) return fail("missing \"jsonrpc\"");
  if (!jsonrpc->is_string() || jsonrpc->get_ref<const std::string&>() != "2.0") {
    return fail("\"jsonrpc\" must be \"2.0\"");
  }

  const auto method = document.find("method");
  if (method == document.end()) return fail("missing \"method\"");
  if (!method->is_string()) return fail(fmt::format("\"method\" must be a string, got {}", method->type_name()));
  request.method = method->get<std::string>();

  if (auto params = document.find("params"); params != document.end()) {
    if (!params->is_object() && !params->is_array() && !params->is_null()) {
      return fail(fmt::format("\"params\" must be an object or an array, got {}", params->type_name()));
    }
    request.params = std::move(*params);
  }

  for (const auto& [key, value] : document.items()) {
    if (key != "jsonrpc" && key != "method" && key != "params" && key != "id") {
      return fail(fmt::format("unknown member \"{}\"", key));
    }
  }
  return request;
}

// JSON cannot carry NaN or infinity, but clients do send them (Python writes NaN and
// Infinity, and 1e999 overflows). The contract answers non-finite values with -32602,
// so a line that failed to parse is retried with such tokens replaced by marker
// strings, which become non-finite numbers again once the document is built.
constexpr std::string_view kNonFiniteMarker = "\x01wheeltec-non-finite:";
constexpr std::string_view kNonFiniteMarkerEscaped = "\\u0001wheeltec-non-finite:";

std::optional<double> non_finite_token(std::string_view token) {
  if (token == "NaN" || token == "-NaN") return std::numeric_limits<double>::quiet_NaN();
  if (token == "Infinity" || token == "+Infinity") return std::numeric_limits<double>::infinity();
  if (token == "-Infinity") return -std::numeric_limits<double>::infinity();
  if (token.empty() || (token[0] != '-' && (token[0] < '0' || token[0] > '9'))) return std::nullopt;
  double value = 0.0;
  const auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  if (result.ec != std::errc::result_out_of_range || result.ptr != token.data() + token.size()) return std::nullopt;
  // Out of range is also reported for underflow (1e-999), which nlohmann accepts as 0.
  const auto exponent = token.find_first_of("eE");
  if (exponent != std::string_view::npos && exponent + 1 < token.size() && token[exponent + 1] == '-') {
    return std::nullopt;
  }
  return token[0] == '-' ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
}

std::optional<std::string> mark_non_finite(std::string_view line) {
  std::string out;
  out.reserve(line.size() + 64);
  bool changed = false;
  std::size_t i = 0;
  auto is_token_char = [](char c) {
    return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '-' || c == '+' ||
           c == '.';
  };
  while (i < line.size()) {
    const char c = line[i];
    std::size_t j = i + 1;
    if (c == '"') {
      while (j < line.size() && line[j] != '"') j += line[j] == '\\' ? 2 : 1;
      j = std::min(j + 1, line.size());
      out.append(line.substr(i, j - i));
    } else if (is_token_char(c)) {
      while (j < line.size() && is_token_char(line[j])) ++j;
      const std::string_view token = line.substr(i, j - i);
      if (const auto value = non_finite_token(token)) {
        out += '"';
        out += kNonFiniteMarkerEscaped;
        out += std::isnan(*value) ? "nan" : *value > 0 ? "+inf" : "-inf";
        out += '"';
        changed = true;
      } else {
        out.append(token);
      }
    } else {
      out += c;
    }
    i = j;
  }
  if (!changed) return std::nullopt;
  return out;
}

// Depth is bounded by kMaxDepth here, since deeper containers were dropped.
void restore_non_finite(json& value) {
  if (value.is_structured()) {
    for (json& child : value) restore_non_finite(child);
    return;
  }
  if (!value.is_string()) return;
  const std::string& text = value.get_ref<const std::string&>();
  if (text.compare(0, kNonFiniteMarker.size(), kNonFiniteMarker) != 0) return;
  const std::string_view kind = std::string_view(text).substr(kNonFiniteMarker.size());
  if (kind == "nan") {
    value = std::numeric_limits<double>::quiet_NaN();
  } else if (kind == "+inf") {
    value = std::numeric_limits<double>::infinity();
  } else if (kind == "-inf") {
    value = -std::numeric_limits<double>::infinity();
  }
}

std::variant<Request, Error> parse_line(std::string_view line) {
  // An unparsable line is -32700 (spec section 2), however deep it was.
  json_text::StrictRead read = json_text::read_strict(line, kMaxDepth);
  if (read.syntax_error) {
    const Error parse_error{kParseError, *read.syntax_error, nullptr};
    const auto marked = mark_non_finite(line);
    if (!marked) return parse_error;
    read = json_text::read_strict(*marked, kMaxDepth);
    if (read.syntax_error) return parse_error;
    restore_non_finite(read.document);
  }
  json& document = read.document;

  if (document.is_array()) return Error{kInvalidRequest, "batch requests are not supported", nullptr};
  if (!document.is_object()) {
    return Error{kInvalidRequest, fmt::format("request must be a JSON object, got {}", document.type_name()), nullptr};
  }
  return parse_object(document, read);
}

}  // namespace

std::variant<Request, Error> parse_request(std::string_view line) {
  try {
    return parse_line(line);
  } catch (const std::exception& error) {
    return Error{kInternalError, fmt::format("cannot process request: {}", printable(error.what())), nullptr};
  }
}

std::string encode_result(const json& id, const json& result) {
  return fmt::format("{{\"jsonrpc\":\"2.0\",\"result\":{},\"id\":{}}}\n", dump(result), dump(id));
}

std::string encode_error(const Error& error) {
  const std::string data = error.data.is_null() ? std::string() : ",\"data\":" + dump(error.data);
  return fmt::format("{{\"jsonrpc\":\"2.0\",\"error\":{{\"code\":{},\"message\":{}{}}},\"id\":{}}}\n", error.code,
                     dump(json(error.message)), data, dump(error.id));
}

std::string encode_notification(std::string_view method, const json& params) {
  if (params.is_null()) return fmt::format("{{\"jsonrpc\":\"2.0\",\"method\":{}}}\n", dump(json(method)));
  return fmt::format("{{\"jsonrpc\":\"2.0\",\"method\":{},\"params\":{}}}\n", dump(json(method)), dump(params));
}

std::variant<Velocity, Error> parse_drive_params(const Request& request, ChassisType chassis) {
  Velocity velocity;
  const json& params = request.params;
  if (params.is_null()) return velocity;
  if (!params.is_object()) {
    return invalid_params(request, "drive params must be an object {\"vx\", \"vy\", \"wz\"}");
  }
  if (auto problem = read_drive_velocity(params, velocity)) return invalid_params(request, *problem);
  if (velocity.vy != 0.0 && !is_holonomic(chassis)) {
    return invalid_params(request, fmt::format("vy must be 0 on a {} chassis", to_string(chassis)));
  }
  return velocity;
}

std::optional<Error> expect_no_params(const Request& request) {
  const json& params = request.params;
  if (params.is_null() || ((params.is_object() || params.is_array()) && params.empty())) return std::nullopt;
  return invalid_params(request, fmt::format("\"{}\" takes no params", request.method));
}

std::variant<std::vector<std::string>, Error> parse_topics(const Request& request) {
  const json& params = request.params;
  if (!params.is_object()) {
    return invalid_params(request, "params must be an object {\"topics\": [...]}");
  }
  for (const auto& [key, value] : params.items()) {
    if (key != "topics") return invalid_params(request, fmt::format("unknown param \"{}\"", key));
  }
  const auto topics = params.find("topics");
  if (topics == params.end()) return invalid_params(request, "missing param \"topics\"");
  if (!topics->is_array()) {
    return invalid_params(request, fmt::format("\"topics\" must be an array, got {}", topics->type_name()));
  }
  if (topics->empty()) return invalid_params(request, "\"topics\" must not be empty");

  std::vector<std::string> names;
  for (const json& topic : *topics) {
    if (!topic.is_string()) {
      return invalid_params(request, fmt::format("unknown topic {} (known: {}, {}, {})", dump(topic), kTopicTelemetry,
                                                 kTopicStatus, kTopicEvents));
    }
    const std::string& name = topic.get_ref<const std::string&>();
    if (name != kTopicTelemetry && name != kTopicStatus && name != kTopicEvents) {
      return invalid_params(request, fmt::format("unknown topic \"{}\" (known: {}, {}, {})", name, kTopicTelemetry,
                                                 kTopicStatus, kTopicEvents));
    }
    bool seen = false;
    for (const std::string& existing : names) seen = seen || existing == name;
    if (!seen) names.push_back(name);
  }
  return names;
}

std::variant<std::string_view, Error> parse_estop_params(const Request& request) {
  const json& params = request.params;
  const bool empty = params.is_null() || (params.is_array() && params.empty()) || (params.is_object() && params.empty());
  if (empty) return std::string_view();
  if (!params.is_object()) return invalid_params(request, "params must be an object {\"reason\": \"...\"}");
  for (const auto& [key, value] : params.items()) {
    if (key != "reason") return invalid_params(request, fmt::format("unknown param \"{}\"", key));
  }
  const json& reason = params.at("reason");
  if (!reason.is_string()) {
    return invalid_params(request, fmt::format("reason must be a string, got {}", reason.type_name()));
  }
  const std::string& value = reason.get_ref<const std::string&>();
  const std::size_t characters = character_count(value);
  if (characters > kMaxEstopReasonCharacters) {
    return invalid_params(request, fmt::format("reason has {} characters, more than the {} it may have", characters,
                                               kMaxEstopReasonCharacters));
  }
  return std::string_view(value);
}

std::variant<std::string_view, Error> parse_mark_params(const Request& request) {
  const json& params = request.params;
  if (!params.is_object()) return invalid_params(request, "params must be an object {\"text\": \"...\"}");
  for (const auto& [key, value] : params.items()) {
    if (key != "text") return invalid_params(request, fmt::format("unknown param \"{}\"", key));
  }
  const auto text = params.find("text");
  if (text == params.end()) return invalid_params(request, "missing param \"text\"");
  if (!text->is_string()) return invalid_params(request, fmt::format("text must be a string, got {}", text->type_name()));
  const std::string& value = text->get_ref<const std::string&>();
  const std::size_t characters = character_count(value);
  if (characters > kMaxMarkCharacters) {
    return invalid_params(request, fmt::format("text has {} characters, more than the {} a mark may have", characters,
                                               kMaxMarkCharacters));
  }
  return std::string_view(value);
}

}  // namespace wheeltec::rpc
