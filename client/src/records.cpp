#include "wheeltec/client/records.hpp"

#include <type_traits>

namespace wheeltec::client {
namespace {

Vector3 vector_from_json(const Json& value) {
  return {value.at("x").get<double>(), value.at("y").get<double>(), value.at("z").get<double>()};
}

Velocity velocity_from_json(const Json& value) {
  return {value.at("vx").get<double>(), value.at("vy").get<double>(), value.at("wz").get<double>()};
}

}  // namespace

Telemetry telemetry_from_json(const Json& record) {
  Telemetry telemetry;
  telemetry.seq = record.at("seq").get<std::uint64_t>();
  telemetry.time = record.at("time").get<double>();
  telemetry.stopped = record.at("stopped").get<bool>();
  telemetry.velocity = velocity_from_json(record.at("velocity"));
  telemetry.accel = vector_from_json(record.at("accel"));
  telemetry.gyro = vector_from_json(record.at("gyro"));
  telemetry.battery_voltage = record.at("battery").at("voltage").get<double>();
  telemetry.battery_low = record.at("battery").at("low").get<bool>();
  const Json& odom = record.at("odom");
  telemetry.odom = {odom.at("x").get<double>(), odom.at("y").get<double>(), odom.at("yaw").get<double>()};
  if (const auto found = record.find("orientation"); found != record.end()) {
    const Json& o = *found;
    telemetry.orientation = Orientation{o.at("w").get<double>(),    o.at("x").get<double>(),
                                        o.at("y").get<double>(),    o.at("z").get<double>(),
                                        o.at("roll").get<double>(), o.at("pitch").get<double>(),
                                        o.at("yaw").get<double>()};
  }
  telemetry.json = record;
  return telemetry;
}

Status status_from_json(const Json& status) {
  Status out;
  const Json& bus = status.at("bus");
  out.bus_transport = bus.value("transport", "can");
  out.bus_interface = bus.value("interface", "");
  out.bus_state = bus.at("state").get<std::string>();
  const Json& chassis = status.at("chassis");
  out.online = chassis.at("online").get<bool>();
  out.stopped = chassis.value("stopped", false);
  out.battery_voltage = chassis.value("battery_v", 0.0);
  out.battery_low = chassis.value("battery_low", false);
  if (const auto phase = chassis.find("phase"); phase != chassis.end() && phase->is_string()) {
    out.phase = phase->get<std::string>();
  }
  out.commands_ignored = chassis.value("commands_ignored", false);
  const Json& control = status.at("control");
  out.control_enabled = control.at("enabled").get<bool>();
  if (const Json& owner = control.at("owner"); !owner.is_null()) out.owner = owner.get<std::uint64_t>();
  out.target = velocity_from_json(control.at("target"));
  if (const auto sent = control.find("sent"); sent != control.end()) out.sent = velocity_from_json(*sent);
  if (const auto safety = status.find("safety"); safety != status.end()) {
    Safety typed;
    typed.latched = safety->at("latched").get<bool>();
    const auto optional_member = [&](const char* key, auto& target) {
      using Value = typename std::remove_reference_t<decltype(target)>::value_type;
      if (const auto member = safety->find(key); member != safety->end() && !member->is_null()) {
        target = member->get<Value>();
      }
    };
    optional_member("source", typed.source);
    optional_member("reason", typed.reason);
    optional_member("since", typed.since);
    optional_member("by", typed.by);
    out.safety = std::move(typed);
  }
  out.json = status;
  return out;
}

Json to_json(const Velocity& velocity) { return {{"vx", velocity.vx}, {"vy", velocity.vy}, {"wz", velocity.wz}}; }

}  // namespace wheeltec::client
