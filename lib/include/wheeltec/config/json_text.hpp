#pragma once

// Reading JSON text written by people and programs (config files, RPC lines): what
// nlohmann's parser hides or words for its own authors.

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace wheeltec::json_text {

// What the parser saw that the document built from it no longer shows.
struct Findings {
  bool too_deep = false;                     // containers nested deeper than the limit were dropped
  std::optional<std::string> duplicate_key;  // the first key repeated within one object (nlohmann keeps the last)
  std::string duplicate_path;                // where: "can.interface", "api.control_users[1].x"
  int duplicate_depth = 0;                   // 1: in the top-level object
};

// Parses `text`, dropping containers nested `max_depth` deep or deeper and noting
// duplicate keys. Throws nlohmann::json::exception as json::parse does.
nlohmann::json parse(std::string_view text, Findings& findings, int max_depth);

// Deeper than any message a bridge takes from a peer (an MQTT command, a Foxglove client's).
inline constexpr int kMaxMessageDepth = 8;

// Why a peer's text is not acted on. `message` is worded for the peer: the parser's
// message, "nested deeper than 8 levels", "duplicate key \"vx\"".
struct Refusal {
  enum class Reason { not_json, too_deep, duplicate_key };
  Reason reason;
  std::string message;
};

// A peer's text (an RPC line, an MQTT payload, a Foxglove message) read strictly:
// containers nested `max_depth` deep or deeper are refused as such (found while reading,
// whether or not the text goes on to parse), then text that does not parse, then a key
// given twice (which nlohmann would silently resolve to its last value): what a peer meant
// is never guessed at.
struct StrictRead {
  nlohmann::json document;                  // as far as it was read: null when not JSON
  Findings findings;
  std::optional<std::string> syntax_error;  // the parser's message when the text is not JSON
  std::optional<Refusal> refusal;           // set: the document must not be acted on
};
StrictRead read_strict(std::string_view text, int max_depth);

// The parser's message without nlohmann's "[json.exception.parse_error.101] " tag, printable.
std::string message(const nlohmann::json::exception& error);

// `text` with control bytes and bytes outside ASCII written as \xHH: parser messages
// quote the offending input, which may be invalid UTF-8.
std::string printable(std::string_view text);

}  // namespace wheeltec::json_text
