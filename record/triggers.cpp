#include "triggers.hpp"

#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "wheeltec/config/config_document.hpp"

namespace wheeltec::record {
namespace {

Trigger known_trigger(const std::string& name, std::string_view option) {
  if (auto trigger = trigger_of_name(name)) return *trigger;
  std::vector<std::string_view> names;
  for (const Trigger each : kTriggers) names.push_back(trigger_name(each));
  throw ConfigError(std::string(option),
                    fmt::format("unknown trigger \"{}\" (the triggers: {})", name, fmt::join(names, ", ")));
}

}  // namespace

TriggerSet::TriggerSet(std::initializer_list<Trigger> triggers) {
  for (const Trigger trigger : triggers) insert(trigger);
}

std::vector<Trigger> TriggerSet::members() const {
  std::vector<Trigger> members;
  for (const Trigger trigger : kTriggers) {
    if (contains(trigger)) members.push_back(trigger);
  }
  return members;
}

TriggerSet default_triggers() {
  TriggerSet all;
  for (const Trigger trigger : kTriggers) all.insert(trigger);
  all.erase(Trigger::refused);
  return all;
}

TriggerSet apply_trigger_options(TriggerSet base, const std::vector<std::string>& enable,
                                 const std::vector<std::string>& disable) {
  for (const std::string& name : enable) base.insert(known_trigger(name, "--trigger"));
  for (const std::string& name : disable) {
    const Trigger trigger = known_trigger(name, "--no-trigger");
    if (std::find(enable.begin(), enable.end(), name) != enable.end()) {
      throw ConfigError("--no-trigger", fmt::format("\"{}\" is also given to --trigger", name));
    }
    base.erase(trigger);
  }
  return base;
}

}  // namespace wheeltec::record
