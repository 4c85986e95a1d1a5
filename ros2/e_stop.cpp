#include "e_stop.hpp"

namespace wheeltec::ros2 {

EStop e_stop_of(const client::Status& status) {
  if (!status.safety || !status.safety->latched) return {};
  return EStop{true, status.safety->source.value_or(""), status.safety->reason.value_or("")};
}

std::string describe_latched(const EStop& e_stop) {
  std::string text = "emergency stop latched";
  if (!e_stop.source.empty()) text += " by " + e_stop.source;
  if (!e_stop.reason.empty()) text += ": " + e_stop.reason;
  return text;
}

}  // namespace wheeltec::ros2
