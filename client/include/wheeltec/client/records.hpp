#pragma once

// The daemon's telemetry record and status object as typed values (docs/api.md).

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace wheeltec::client {

// Ordered: objects keep the daemon's key order, so a program can print them as sent.
using Json = nlohmann::ordered_json;

struct Velocity {
  double vx = 0.0;  // m/s
  double vy = 0.0;  // m/s
  double wz = 0.0;  // rad/s
};

struct Vector3 {
  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
};

struct Pose2D {
  double x = 0.0;    // m
  double y = 0.0;    // m
  double yaw = 0.0;  // rad, (-pi, pi]
};

struct Orientation {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;  // unit quaternion
  double roll = 0.0, pitch = 0.0, yaw = 0.0;  // rad
};

struct Telemetry {
  std::uint64_t seq = 0;
  double time = 0.0;  // seconds since the epoch
  bool stopped = false;
  Velocity velocity;
  Vector3 accel;  // m/s^2
  Vector3 gyro;   // rad/s
  double battery_voltage = 0.0;
  bool battery_low = false;
  Pose2D odom;
  std::optional<Orientation> orientation;  // protocol 2 and later
  Json json;  // the whole record, for fields not typed here
};

// The emergency stop (protocol 5): latched until a client with control rights releases it.
struct Safety {
  bool latched = false;
  std::optional<std::string> source;  // "client", "collision", "tilt", "stall" while latched
  std::optional<std::string> reason;  // the caller's text ("" when none) or a hazard's figures
  std::optional<double> since;        // seconds since the epoch
  std::optional<std::uint64_t> by;    // the client that called estop
};

struct Status {
  std::string bus_transport = "can";  // "can" or "serial" (protocol 3; a protocol 2 daemon speaks CAN)
  std::string bus_interface;          // the CAN interface or the serial device, as configured
  std::string bus_state;              // "up", "down", "error-passive", "bus-off"
  bool online = false;
  std::optional<std::string> phase;  // "booting", "self-test", "ready", "halted"; empty while offline
  bool commands_ignored = false;
  bool stopped = false;
  double battery_voltage = 0.0;
  bool battery_low = false;
  bool control_enabled = false;
  std::optional<std::uint64_t> owner;  // id of the client holding control
  Velocity target;
  Velocity sent;                 // what the last control frame carried (protocol 5; zero before)
  std::optional<Safety> safety;  // empty from a daemon before protocol 5
  Json json;  // the whole object, for fields not typed here
};

// Throw nlohmann::json::exception when a field the API guarantees is missing or mistyped.
Telemetry telemetry_from_json(const Json& record);
Status status_from_json(const Json& status);
Json to_json(const Velocity& velocity);

}  // namespace wheeltec::client
