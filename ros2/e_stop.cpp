#include "e_stop.hpp"

namespace wheeltec::ros2 {
namespace {

std::string text_member(const client::Json& object, const char* key) {
  const auto found = object.find(key);
  return found != object.end() && found->is_string() ? found->get<std::string>() : std::string();
}

}  // namespace

EStop e_stop_of(const client::Status& status) {
  const auto safety = status.json.find("safety");
  if (safety == status.json.end() || !safety->is_object()) return {};
  const auto latched = safety->find("latched");
  if (latched == safety->end() || *latched != true) return {};
  return EStop{true, text_member(*safety, "source"), text_member(*safety, "reason")};
}

std::string describe_latched(const EStop& e_stop) {
  std::string text = "emergency stop latched";
  if (!e_stop.source.empty()) text += " by " + e_stop.source;
  if (!e_stop.reason.empty()) text += ": " + e_stop.reason;
  return text;
}

}  // namespace wheeltec::ros2
