#include "calibration_report.hpp"

#include <fmt/format.h>

namespace wheeltecctl {
namespace {

namespace cal = wheeltec::calibration;

std::string amount_text(cal::Axis axis, double value) {
  return axis == cal::Axis::linear ? fmt::format("{:.3f} m", value) : fmt::format("{:.1f} degrees", value);
}

}  // namespace

std::optional<double> reported_scale(const Json& status, cal::ScaleKey key) {
  if (!status.is_object()) return std::nullopt;
  const auto odometry = status.find("odometry");
  if (odometry == status.end() || !odometry->is_object()) return std::nullopt;
  const auto scale = odometry->find("scale");
  if (scale == odometry->end() || !scale->is_object()) return std::nullopt;
  const auto factor = scale->find(std::string(cal::scale_key_name(key)));
  if (factor == scale->end() || !factor->is_number()) return std::nullopt;
  return factor->get<double>();
}

std::string calibration_prompt(cal::Axis axis, double odometry) {
  if (axis == cal::Axis::linear) {
    return fmt::format(
        "The odometry says the robot went {}.\n"
        "Measure the straight distance from the start mark to the end mark.\n"
        "Metres measured (empty line aborts): ",
        amount_text(axis, odometry));
  }
  return fmt::format(
      "The odometry says the robot turned {} ({:.2f} turns).\n"
      "Count the whole turns (360 degrees each) and add how far past the heading mark it\n"
      "stopped (subtract if it stopped short of it).\n"
      "Degrees measured (empty line aborts): ",
      amount_text(axis, odometry), odometry / 360.0);
}

std::string calibration_retry(cal::Axis axis, const std::string& reason) {
  return reason + (axis == cal::Axis::linear ? "; enter the metres measured, e.g. 0.973"
                                             : "; enter the degrees measured, e.g. 372.5");
}

Json calibration_json(const CalibrationResult& result) {
  return Json{{"axis", std::string(cal::scale_key_name(result.key))},
              {"odometry", result.odometry},
              {"measured", result.measured},
              {"current", result.current},
              {"scale", result.scale}};
}

std::string format_calibration(const CalibrationResult& result) {
  const std::string_view key = cal::scale_key_name(result.key);
  return fmt::format(
      "odometry.scale.{0} = {1:.3f}\n"
      "(odometry {2}, measured {3}, current factor {4:.3f})\n"
      "To apply it, set \"{0}\": {1:.3f} in the \"odometry\": {{\"scale\": {{...}}}} object of\n"
      "/etc/wheeltecd/wheeltecd.json, then: sudo systemctl reload wheeltecd (or send wheeltecd\n"
      "SIGHUP). The new factor applies from the next record.\n",
      key, result.scale, amount_text(result.axis, result.odometry), amount_text(result.axis, result.measured),
      result.current);
}

}  // namespace wheeltecctl
