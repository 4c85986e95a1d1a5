#include "trigger_detector.hpp"

namespace wheeltec::record {
namespace {

const Json* member(const Json& object, const char* key) {
  if (!object.is_object()) return nullptr;
  const auto found = object.find(key);
  return found == object.end() ? nullptr : &*found;
}

// `key` of `object` as a bool (null as false); `previous` when missing or of another type.
bool flag(const Json* object, const char* key, bool previous) {
  const Json* value = object ? member(*object, key) : nullptr;
  if (!value) return previous;
  if (value->is_null()) return false;
  return value->is_boolean() ? value->get<bool>() : previous;
}

std::optional<Trigger> trigger_of_event(const Json& event) {
  const Json* kind = member(event, "event");
  if (!kind || !kind->is_string()) return std::nullopt;
  const auto& name = kind->get_ref<const std::string&>();
  if (name == "deadman") return Trigger::deadman;
  if (name == "refused") return Trigger::refused;
  if (name == "mark") return Trigger::mark;
  if (name == "estop") return Trigger::estop;
  return std::nullopt;
}

}  // namespace

TriggerDetector::TriggerDetector(TriggerSet enabled) : enabled_(enabled) {}

TriggerDetector::Watched TriggerDetector::read_watched(const Json& status, const Watched& previous) {
  Watched now = previous;
  const Json* bus = member(status, "bus");
  if (const Json* state = bus ? member(*bus, "state") : nullptr; state && state->is_string()) {
    now.bus_state = state->get<std::string>();
  }
  const Json* chassis = member(status, "chassis");
  if (const Json* phase = chassis ? member(*chassis, "phase") : nullptr) {
    if (phase->is_string()) now.phase = phase->get<std::string>();
    if (phase->is_null()) now.phase.reset();
  }
  now.online = flag(chassis, "online", previous.online);
  now.battery_low = flag(chassis, "battery_low", previous.battery_low);
  now.commands_ignored = flag(chassis, "commands_ignored", previous.commands_ignored);
  return now;
}

void TriggerDetector::fire(std::vector<FiredTrigger>& fired, Trigger trigger, RealtimeNanos time) const {
  if (enabled_.contains(trigger)) fired.push_back({trigger, time});
}

std::vector<FiredTrigger> TriggerDetector::on_status(const Json& status, RealtimeNanos received) {
  std::vector<FiredTrigger> fired;
  auto* baseline = std::get_if<Baseline>(&state_);
  if (!baseline) {
    const Watched first = read_watched(status, Watched{});
    state_ = Baseline{first, first.phase == "ready" ? SinceBoot::been_ready : SinceBoot::not_ready_yet};
    return fired;
  }
  const Watched before = baseline->last;
  const Watched now = read_watched(status, before);
  const auto became = [&](const char* phase) { return now.phase == phase && before.phase != phase; };

  if (became("halted")) fire(fired, Trigger::halted, received);
  if (became("booting")) {
    if (baseline->since_boot == SinceBoot::been_ready) fire(fired, Trigger::reboot, received);
    baseline->since_boot = SinceBoot::not_ready_yet;
  }
  if (now.phase == "ready") baseline->since_boot = SinceBoot::been_ready;
  if (before.bus_state == "up" && now.bus_state != "up") fire(fired, Trigger::link_down, received);
  if (before.online && !now.online) fire(fired, Trigger::offline, received);
  if (!before.battery_low && now.battery_low) fire(fired, Trigger::battery_low, received);
  if (!before.commands_ignored && now.commands_ignored) fire(fired, Trigger::commands_ignored, received);
  baseline->last = now;
  return fired;
}

std::optional<FiredTrigger> TriggerDetector::on_event(const Json& event, RealtimeNanos received) {
  const std::optional<Trigger> trigger = trigger_of_event(event);
  if (!trigger || !enabled_.contains(*trigger)) return std::nullopt;
  return FiredTrigger{*trigger, time_of_message(event).value_or(received)};
}

std::optional<FiredTrigger> TriggerDetector::on_daemon_lost(RealtimeNanos at) {
  state_ = NoBaseline{};
  if (!enabled_.contains(Trigger::daemon_lost)) return std::nullopt;
  return FiredTrigger{Trigger::daemon_lost, at};
}

}  // namespace wheeltec::record
