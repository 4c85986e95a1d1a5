#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "wheeltec/chassis_phase.hpp"
#include "wheeltec/control_arbiter.hpp"
#include "wheeltec/control_frame.hpp"
#include "wheeltec/emergency_stop.hpp"
#include "wheeltec/odometry.hpp"
#include "wheeltec/velocity_ramp.hpp"
#include "wheeltec/types.hpp"

#include "wheeltec/bus_state.hpp"

namespace wheeltec::daemon {

// What the status object says of a present dock.
struct DockStatus {
  bool charging = false;
  std::array<bool, 4> ir{};
  friend bool operator==(const DockStatus&, const DockStatus&) = default;
};

// Which latch holds, enough to tell one from the next (a latch's reason never changes).
struct LatchMark {
  LatchSource source = LatchSource::client;
  RealtimeNanos since{};
  friend bool operator==(const LatchMark&, const LatchMark&) = default;
};

// The status fields whose change is announced to status subscribers: everything but
// uptime_s and telemetry_age_s. Cheap to build and compare on every record.
struct StatusFields {
  BusState bus_state = BusState::down;
  bool online = false;
  std::optional<bool> stopped;
  std::optional<double> battery_v;  // rounded to 0.01 V
  std::optional<bool> battery_low;
  std::optional<ChassisPhase> phase;  // empty while offline
  bool commands_ignored = false;
  std::optional<DockStatus> dock;     // empty while no dock is present
  bool control_enabled = false;
  std::optional<ClientId> owner;
  Velocity target;
  Velocity sent;                 // what the last control frame carried
  VelocityLimits limits;         // these three change on SIGHUP
  RampLimits ramp;
  OdometryScale odometry_scale;
  std::optional<LatchMark> latch;
  friend bool operator==(const StatusFields&, const StatusFields&) = default;
};

// What the status object says that never changes while the daemon runs.
struct StatusIdentity {
  Transport transport = Transport::can;
  std::string_view interface;  // the CAN interface or the serial device, as configured
  ChassisType chassis_type = ChassisType::mecanum;
  Dialect dialect = Dialect::manual;  // shown on CAN only
};

double round_battery_v(double volts);  // to 0.01 V

// The line systemd shows in `systemctl status` (STATUS=).
std::string status_line(const StatusFields& fields, std::uint64_t clients);

// The status object of spec section 2.
nlohmann::json status_to_json(const StatusIdentity& identity, const StatusFields& fields, double uptime_s,
                              std::optional<double> telemetry_age_s, const SafetyState& safety = std::nullopt);

}  // namespace wheeltec::daemon
