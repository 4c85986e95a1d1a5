#pragma once

// The hazards of spec section 12: collision, tilt and stall, each judged on the telemetry
// records the daemon accepts while the chassis is ready, each a source of the emergency
// stop's latch. Pure: the time is the records' own, the figures come in with each record,
// and a record that finds nothing allocates nothing.

#include <optional>
#include <string>

#include "wheeltec/clocks.hpp"
#include "wheeltec/control/emergency_stop.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

// safety.collision, safety.tilt, safety.stall (defaults as the spec's).
struct CollisionLimits {
  bool enabled = true;
  double drop = 0.25;  // m/s
  friend bool operator==(const CollisionLimits&, const CollisionLimits&) = default;
};
struct TiltLimits {
  bool enabled = true;
  double max_deg = 35.0;
  double for_s = 0.3;
  friend bool operator==(const TiltLimits&, const TiltLimits&) = default;
};
struct StallLimits {
  bool enabled = true;
  double for_s = 2.0;
  friend bool operator==(const StallLimits&, const StallLimits&) = default;
};
struct HazardLimits {
  CollisionLimits collision;
  TiltLimits tilt;
  StallLimits stall;
  friend bool operator==(const HazardLimits&, const HazardLimits&) = default;
};

// What one accepted record says, and what control asked for when it came.
struct HazardSample {
  RealtimeNanos time;      // the record's
  Velocity measured;       // the record's velocity
  double roll = 0.0;       // rad, the attitude estimate's
  double pitch = 0.0;      // rad
  Velocity target;         // the drive's target (zero when nobody drives)
  Velocity sent;           // the last control frame sent before the record
};

// A hazard found: the latch's source and a reason with the measured figures.
struct HazardFinding {
  LatchSource source = LatchSource::collision;
  std::string reason;
  friend bool operator==(const HazardFinding&, const HazardFinding&) = default;
};

double planar_speed(const Velocity& velocity);

// A fall in planar speed of more than `drop` between two records at most 0.15 s apart,
// while the frame sent asked for at least the later speed + `drop` in the direction the
// robot was moving (a command to reverse is a commanded slow-down too).
class CollisionHazard {
 public:
  static constexpr std::chrono::milliseconds kMaxInterval{150};
  std::optional<HazardFinding> judge(const HazardSample& sample, const CollisionLimits& limits);
  void reset() { previous_.reset(); }

 private:
  struct Seen {
    RealtimeNanos time;
    Velocity measured;
  };
  std::optional<Seen> previous_;
};

// Roll or pitch beyond ±max_deg in every record for for_s, from 1 s after the first record
// (the attitude estimate needs a moment).
class TiltHazard {
 public:
  static constexpr std::chrono::seconds kSettle{1};
  std::optional<HazardFinding> judge(const HazardSample& sample, const TiltLimits& limits);
  void reset();
  // Whether the latest record was beyond max_deg (release is refused meanwhile).
  bool tilted() const { return tilted_; }

 private:
  std::optional<RealtimeNanos> first_record_;
  std::optional<RealtimeNanos> beyond_since_;
  bool tilted_ = false;
};

// Moved under the current drive, then still for for_s while the frames asked for motion.
class StallHazard {
 public:
  static constexpr double kMovedPlanar = 0.05, kMovedTurn = 0.1;   // m/s, rad/s
  static constexpr double kStillPlanar = 0.03, kStillTurn = 0.05;  // m/s, rad/s
  static constexpr double kAskedPlanar = 0.1, kAskedTurn = 0.3;    // m/s, rad/s
  std::optional<HazardFinding> judge(const HazardSample& sample, const StallLimits& limits);
  void reset();

 private:
  bool driving_ = false;  // the target was non-zero at the last record
  bool moved_ = false;    // some record since the target became non-zero showed motion
  std::optional<RealtimeNanos> still_since_;
};

// The three together, as the daemon runs them.
class HazardJudge {
 public:
  explicit HazardJudge(HazardLimits limits = {}) : limits_(limits) {}
  void set_limits(const HazardLimits& limits) { limits_ = limits; }
  const HazardLimits& limits() const { return limits_; }

  // A record accepted while the chassis is ready. While `latched` every hazard keeps
  // watching (tilted() stays true) but none is found: one latch at a time. When several
  // hold at once, the first of collision, tilt, stall is the one found.
  std::optional<HazardFinding> judge(const HazardSample& sample, bool latched);
  // The chassis left ready: each starts over, the tilt's settling second too.
  void reset();
  // The tilt hazard still holds (enabled, and the latest record beyond max_deg).
  bool tilted() const { return limits_.tilt.enabled && tilt_.tilted(); }

 private:
  HazardLimits limits_;
  CollisionHazard collision_;
  TiltHazard tilt_;
  StallHazard stall_;
};

}  // namespace wheeltec
