#include "recorder_config.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/config/config_checks.hpp"
#include "wheeltec/config/config_fields.hpp"


namespace wheeltec::record {
namespace {

using json = nlohmann::json;
using namespace config_fields;

void check_seconds(double value, double low, double high, bool low_inclusive, std::string_view key) {
  const bool above_low = low_inclusive ? value >= low : value > low;
  if (!std::isfinite(value) || !above_low || value > high) {
    fail(key, fmt::format("must be a number of seconds in {}{}, {}], got {}", low_inclusive ? "[" : "(", low, high,
                          value));
  }
}

}  // namespace

// The set a list of trigger names makes; an unknown name fails at its index.
Field trigger_list(std::string_view key, TriggerSet& target) {
  return {key, [key, &target](const json& value, const std::string& path) {
            std::vector<std::string> names;
            text_array(key, names).apply(value, path);
            TriggerSet set;
            for (std::size_t i = 0; i < names.size(); ++i) {
              const auto trigger = trigger_of_name(names[i]);
              if (!trigger) fail(fmt::format("{}[{}]", path, i), fmt::format("unknown trigger \"{}\"", names[i]));
              set.insert(*trigger);
            }
            target = set;
          }};
}

void apply_recorder_config(const json& document, RecorderConfig& config) {
  apply_object(document, "",
               {text("socket", config.socket), text("dir", config.dir), number("before_s", config.before_s),
                number("after_s", config.after_s),
                {"max_bytes",
                 [&](const json& value, const std::string& path) {
                   config.max_bytes =
                       static_cast<std::uint64_t>(read_integer(value, path, 1, std::numeric_limits<std::int64_t>::max()));
                 }},
                boolean("continuous", config.continuous), number("split_s", config.split_s),
                trigger_list("triggers", config.triggers), object("log", {text("level", config.log.level)})});
}

void validate_recorder_config(const RecorderConfig& config) {
  config_checks::check_socket_path(config.socket, "socket");
  if (config.dir.empty()) fail("dir", "must not be empty");
  check_seconds(config.before_s, 0.0, kMaxBeforeS, false, "before_s");
  check_seconds(config.after_s, 0.0, kMaxAfterS, true, "after_s");
  check_seconds(config.split_s, 1.0, 86400.0, true, "split_s");
  if (config.max_bytes == 0) fail("max_bytes", "must be 1 or more");
  config_checks::check_log_level(config.log.level);
}

}  // namespace wheeltec::record
