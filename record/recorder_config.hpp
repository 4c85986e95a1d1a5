#pragma once

// wheeltec-record's configuration (docs/record.md lists every key): defaults, the JSON
// config file over them, then the command line. Pure: no I/O; the file is read by
// options.cpp.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/config/config_document.hpp"  // ConfigError

#include "triggers.hpp"

namespace wheeltec::record {

struct RecorderConfig {
  std::string socket = "/run/wheeltecd/wheeltecd.sock";
  std::string dir = "/var/lib/wheeltec-record";
  double before_s = 60.0;
  double after_s = 10.0;
  std::uint64_t max_bytes = std::uint64_t{1} << 30;
  bool continuous = false;
  double split_s = 600.0;
  // The triggers on (key `triggers`, a list of names); --trigger and --no-trigger change it.
  TriggerSet triggers = default_triggers();
  struct Log {
    std::string level = "info";
  } log;
};

inline constexpr double kMaxBeforeS = 3600.0;
inline constexpr double kMaxAfterS = 600.0;  // a file spans 10 minutes at most anyway

// Merges a document of the config file's shape over `config`; throws ConfigError naming the key.
void apply_recorder_config(const nlohmann::json& document, RecorderConfig& config);

// The whole configuration's value checks; throws ConfigError naming the key.
void validate_recorder_config(const RecorderConfig& config);

}  // namespace wheeltec::record
