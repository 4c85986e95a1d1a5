#include "status_report.hpp"

#include <cmath>

#include <fmt/format.h>

#include "wheeltec/config.hpp"
#include "wheeltec/version.hpp"

namespace wheeltec::daemon {
namespace {

using json = nlohmann::json;

// Divides by an exact power of ten so that e.g. 22.58 prints as 22.58, not 22.580000000000002.
double round_to(double value, double scale) { return std::round(value * scale) / scale; }

template <typename T>
json optional_json(const std::optional<T>& value) {
  return value ? json(*value) : json(nullptr);
}

json phase_json(const std::optional<ChassisPhase>& phase) {
  return phase ? json(to_string(*phase)) : json(nullptr);
}

json dock_json(const std::optional<DockStatus>& dock) {
  if (!dock) return json{{"present", false}};
  return json{{"present", true}, {"charging", dock->charging}, {"ir", dock->ir}};
}

}  // namespace

double round_battery_v(double volts) { return round_to(volts, 100.0); }

std::string status_line(const StatusFields& fields, std::uint64_t clients) {
  std::string line = fmt::format("bus {}, chassis {}", to_string(fields.bus_state), fields.online ? "online" : "offline");
  if (fields.battery_v) line += fmt::format(", battery {:.2f} V", *fields.battery_v);
  line += fmt::format(", {} client{}", clients, clients == 1 ? "" : "s");
  if (fields.control_enabled) line += ", control enabled";
  if (fields.latch) line += fmt::format(", EMERGENCY STOP ({})", to_string(fields.latch->source));
  return line;
}

json status_to_json(const StatusIdentity& identity, const StatusFields& fields, double uptime_s,
                    std::optional<double> telemetry_age_s, const SafetyState& safety) {
  if (telemetry_age_s) telemetry_age_s = round_to(*telemetry_age_s, 1000.0);
  json status{
      {"version", kVersion},
      {"uptime_s", round_to(uptime_s, 1000.0)},
      {"bus",
       {{"transport", to_string(identity.transport)},
        {"interface", identity.interface},
        {"state", to_string(fields.bus_state)}}},
      {"chassis",
       {{"type", to_string(identity.chassis_type)},
        {"online", fields.online},
        {"telemetry_age_s", optional_json(telemetry_age_s)},
        {"stopped", optional_json(fields.stopped)},
        {"battery_v", optional_json(fields.battery_v)},
        {"battery_low", optional_json(fields.battery_low)},
        {"phase", phase_json(fields.phase)},
        {"commands_ignored", fields.commands_ignored}}},
      {"dock", dock_json(fields.dock)},
      {"control",
       {{"enabled", fields.control_enabled},
        {"owner", optional_json(fields.owner)},
        {"target", {{"vx", fields.target.vx}, {"vy", fields.target.vy}, {"wz", fields.target.wz}}},
        {"sent", {{"vx", fields.sent.vx}, {"vy", fields.sent.vy}, {"wz", fields.sent.wz}}},
        {"limits", velocity_limits_to_json(fields.limits)},
        {"accel", axis_rates_to_json(fields.ramp.accel)},
        {"decel", axis_rates_to_json(fields.ramp.decel)}}},
      {"safety", safety_to_json(safety)},
      {"odometry", {{"scale", odometry_scale_to_json(fields.odometry_scale)}}},
  };
  // The dialect is how control frames look on CAN; the serial line has one frame format.
  if (identity.transport == Transport::can) status["chassis"]["dialect"] = to_string(identity.dialect);
  return status;
}

}  // namespace wheeltec::daemon
