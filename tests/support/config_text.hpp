#pragma once
// Config tests' two questions about a config file's text: what it configures, and which
// key it is refused for.

#include <nlohmann/json.hpp>

#include "wheeltec/config/config_document.hpp"

#include <string>

namespace wheeltec::test {

// The config a program makes of `text` through its own apply and validate steps.
template <typename Config, typename Apply, typename Validate>
Config config_from_text(const std::string& text, Apply apply, Validate validate) {
  Config config;
  apply(parse_config_document(text), config);
  validate(config);
  return config;
}

// The key the ConfigError of `parse(text)` names, or "" when the text is accepted.
template <typename Parse>
std::string refused_key_of(Parse parse, const std::string& text) {
  try {
    parse(text);
  } catch (const ConfigError& error) {
    return error.key();
  }
  return "";
}

}  // namespace wheeltec::test
