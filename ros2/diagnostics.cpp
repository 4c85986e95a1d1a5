#include "diagnostics.hpp"

#include <algorithm>

#include "e_stop.hpp"

namespace wheeltec::ros2 {
namespace {

struct Assessment {
  DiagnosticLevel level = DiagnosticLevel::ok;
  std::vector<std::string> problems;

  void add(DiagnosticLevel problem_level, std::string problem) {
    level = std::max(level, problem_level);
    problems.push_back(std::move(problem));
  }
};

// The status object's fields as "chassis.phase" = "ready" and the like.
void flatten(const client::Json& value, const std::string& path,
             std::vector<std::pair<std::string, std::string>>& values) {
  if (value.is_object()) {
    for (const auto& [key, member] : value.items()) flatten(member, path.empty() ? key : path + "." + key, values);
  } else if (value.is_string()) {
    values.emplace_back(path, value.get<std::string>());
  } else {
    values.emplace_back(path, value.dump());
  }
}

Assessment assess(const client::Status& status) {
  Assessment assessment;
  if (const EStop e_stop = e_stop_of(status); e_stop.latched) {
    assessment.add(DiagnosticLevel::error, describe_latched(e_stop));
  }
  if (status.bus_state == "down" || status.bus_state == "bus-off") {
    assessment.add(DiagnosticLevel::error, "link to the chassis " + status.bus_state);
  } else if (status.bus_state != "up") {
    assessment.add(DiagnosticLevel::warn, "link to the chassis " + status.bus_state);
  }
  if (!status.online) {
    assessment.add(DiagnosticLevel::warn, "chassis offline");
  } else if (status.phase && *status.phase != "ready") {
    assessment.add(DiagnosticLevel::warn, "chassis " + *status.phase);
  }
  if (status.battery_low) assessment.add(DiagnosticLevel::warn, "battery low");
  if (status.commands_ignored) assessment.add(DiagnosticLevel::warn, "chassis ignores commands");
  return assessment;
}

}  // namespace

void RefusalRecord::note(Clock::time_point now, std::string message) {
  last_ = now;
  message_ = std::move(message);
}

std::optional<std::string> RefusalRecord::shown(Clock::time_point now) const {
  if (!last_ || now - *last_ >= kShownFor) return std::nullopt;
  return message_;
}

DiagnosticReport diagnose(const std::optional<client::Status>& status, const std::optional<std::string>& refusal,
                          const BridgeCounters& counters) {
  DiagnosticReport report;
  Assessment assessment;
  if (status) {
    assessment = assess(*status);
    report.hardware_id = status->bus_interface;
    flatten(status->json, "", report.values);
  } else {
    assessment.add(DiagnosticLevel::error, "wheeltecd unreachable");
  }
  if (refusal) assessment.add(DiagnosticLevel::warn, "cmd_vel refused: " + *refusal);
  report.level = assessment.level;
  if (assessment.problems.empty()) {
    report.message = "ready";
  } else {
    for (const std::string& problem : assessment.problems) {
      report.message += (report.message.empty() ? "" : "; ") + problem;
    }
  }
  report.values.emplace_back("cmd_vel_received", std::to_string(counters.cmd_vel_received));
  report.values.emplace_back("cmd_vel_dropped_non_finite", std::to_string(counters.cmd_vel_dropped_non_finite));
  report.values.emplace_back("drives_refused", std::to_string(counters.drives_refused));
  return report;
}

}  // namespace wheeltec::ros2
