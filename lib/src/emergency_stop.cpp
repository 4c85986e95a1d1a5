#include "wheeltec/emergency_stop.hpp"

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/json_text.hpp"

namespace wheeltec {
namespace {

using json = nlohmann::json;

constexpr int kFileFormat = 1;

double to_epoch_seconds(RealtimeNanos time) {
  return std::chrono::duration<double>(time.time_since_epoch()).count();
}

}  // namespace

std::string_view to_string(LatchSource source) {
  for (const auto& entry : kLatchSourceNames) {
    if (entry.value == source) return entry.name;
  }
  return "client";
}

json safety_to_json(const SafetyState& state) {
  if (!state) return json{{"latched", false}, {"source", nullptr}, {"reason", nullptr}, {"since", nullptr}, {"by", nullptr}};
  // Two decimals, as the contract shows it; kept exact in the state file.
  const double since = std::round(to_epoch_seconds(state->since) * 100.0) / 100.0;
  return json{{"latched", true},
              {"source", to_string(state->source)},
              {"reason", state->reason},
              {"since", since},
              {"by", state->by ? json(*state->by) : json(nullptr)}};
}

std::string encode_safety_file(const SafetyState& state) {
  json document{{"format", kFileFormat}, {"latched", state.has_value()}};
  if (state) {
    document["source"] = to_string(state->source);
    document["reason"] = state->reason;
    document["since_ns"] = state->since.time_since_epoch().count();
    document["by"] = state->by ? json(*state->by) : json(nullptr);
  }
  return document.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

std::variant<SafetyState, std::string> decode_safety_file(std::string_view text) {
  json document;
  try {
    document = json::parse(text);
  } catch (const json::exception& error) {
    return fmt::format("not JSON ({})", json_text::message(error));
  }
  if (!document.is_object()) return std::string("not a JSON object");
  const auto format = document.find("format");
  if (format == document.end() || !format->is_number_integer() || *format != kFileFormat) {
    return fmt::format("\"format\" is not {}", kFileFormat);
  }
  const auto latched = document.find("latched");
  if (latched == document.end() || !latched->is_boolean()) return std::string("\"latched\" is not a boolean");
  if (!latched->get<bool>()) return SafetyState{};

  Latch latch;
  const auto source = document.find("source");
  if (source == document.end() || !source->is_string()) return std::string("\"source\" is not a string");
  const auto parsed = parse_enum<LatchSource>(source->get_ref<const std::string&>());
  if (!parsed) return fmt::format("unknown source \"{}\"", source->get_ref<const std::string&>());
  latch.source = *parsed;
  const auto reason = document.find("reason");
  if (reason == document.end() || !reason->is_string()) return std::string("\"reason\" is not a string");
  latch.reason = reason->get<std::string>();
  const auto since = document.find("since_ns");
  if (since == document.end() || !since->is_number_integer()) return std::string("\"since_ns\" is not an integer");
  latch.since = RealtimeNanos(std::chrono::nanoseconds(since->get<std::int64_t>()));
  const auto by = document.find("by");
  if (by == document.end() || !(by->is_null() || by->is_number_unsigned())) {
    return std::string("\"by\" is not a client id or null");
  }
  if (by->is_number_unsigned()) latch.by = by->get<ClientId>();
  return SafetyState{std::move(latch)};
}

Latch damaged_file_latch(std::string_view problem, RealtimeNanos now) {
  return Latch{LatchSource::client,
               fmt::format("the safety state file could not be read ({}): latched to be safe", problem), now,
               std::nullopt};
}

}  // namespace wheeltec
