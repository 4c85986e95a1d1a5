#include "wheeltec/config/config_document.hpp"

#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/json_text.hpp"

namespace wheeltec {
namespace {

using json = nlohmann::json;

// Deeper than any config file: refused before the document is walked.
constexpr int kMaxDepth = 16;

std::string syntax_error_message(const json::parse_error& error) {
  // nlohmann: "[json.exception.parse_error.101] parse error at line 2, column 5: syntax error while parsing ..."
  const std::string message = json_text::message(error);
  std::string_view what = message;
  const auto at = what.find(" at line ");
  std::string_view detail;
  std::string location;
  if (at != std::string_view::npos) {
    const auto colon = what.find(": ", at);
    location = std::string(what.substr(at, colon == std::string_view::npos ? what.npos : colon - at));
    if (colon != std::string_view::npos) detail = what.substr(colon + 2);
  } else {
    location = fmt::format(" at byte {}", error.byte);
    const auto bracket = what.find("] ");
    detail = bracket == std::string_view::npos ? what : what.substr(bracket + 2);
  }
  constexpr std::string_view kPrefix = "syntax error while ";
  if (detail.substr(0, kPrefix.size()) == kPrefix) detail.remove_prefix(kPrefix.size());
  return fmt::format("config: syntax error{}: {}", location, detail);
}

}  // namespace

ConfigError::ConfigError(std::string key, std::string_view problem)
    : std::runtime_error(fmt::format("{}: {}", key, problem)), key_(std::move(key)) {}

json parse_config_document(std::string_view text) {
  json_text::Findings findings;
  json document;
  try {
    document = json_text::parse(text, findings, kMaxDepth);
  } catch (const json::parse_error& error) {
    throw ConfigError(syntax_error_message(error));
  } catch (const json::exception& error) {
    // e.g. out_of_range 406 for a number that overflows a double (1e999)
    throw ConfigError(fmt::format("config: {}", json_text::message(error)));
  }
  if (findings.too_deep) throw ConfigError(fmt::format("config: nested deeper than {} levels", kMaxDepth));
  if (findings.duplicate_key) throw ConfigError(findings.duplicate_path, "duplicate key");
  return document;
}

}  // namespace wheeltec
