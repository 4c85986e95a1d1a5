#include "wheeltec/control/hazards.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "wheeltec/telemetry/calibration.hpp"

namespace wheeltec {
namespace {

using calibration::degrees;
using calibration::radians;

double seconds_between(RealtimeNanos from, RealtimeNanos to) {
  return std::chrono::duration<double>(to - from).count();
}

// How long `holds` has held without a break, up to `now`; empty when it does not hold now.
std::optional<double> held_for(std::optional<RealtimeNanos>& since, bool holds, RealtimeNanos now) {
  if (!holds) {
    since.reset();
    return std::nullopt;
  }
  if (!since) since = now;
  return seconds_between(*since, now);
}

}  // namespace

double planar_speed(const Velocity& velocity) { return std::hypot(velocity.vx, velocity.vy); }

std::optional<HazardFinding> CollisionHazard::judge(const HazardSample& sample, const CollisionLimits& limits) {
  const double speed = planar_speed(sample.measured);
  const std::optional<Seen> previous = std::exchange(previous_, Seen{sample.time, sample.measured});
  if (!limits.enabled || !previous) return std::nullopt;
  const auto interval = sample.time - previous->time;
  if (interval <= std::chrono::nanoseconds::zero() || interval > kMaxInterval) return std::nullopt;
  const double previous_speed = planar_speed(previous->measured);
  if (previous_speed - speed <= limits.drop) return std::nullopt;
  // The command's part along the way the robot was going (previous_speed > drop > 0).
  const double asked = (sample.sent.vx * previous->measured.vx + sample.sent.vy * previous->measured.vy) / previous_speed;
  if (asked < speed + limits.drop) return std::nullopt;
  return HazardFinding{
      LatchSource::collision,
      fmt::format("planar speed fell from {:.2f} to {:.2f} m/s in {:.2f} s while the command asked for {:.2f} m/s",
                  previous_speed, speed, seconds_between(previous->time, sample.time), asked)};
}

void TiltHazard::reset() {
  first_record_.reset();
  beyond_since_.reset();
  tilted_ = false;
}

std::optional<HazardFinding> TiltHazard::judge(const HazardSample& sample, const TiltLimits& limits) {
  if (!first_record_) first_record_ = sample.time;
  const double limit = radians(limits.max_deg);
  tilted_ = std::abs(sample.roll) > limit || std::abs(sample.pitch) > limit;
  const auto held = held_for(beyond_since_, tilted_ && sample.time >= *first_record_ + kSettle, sample.time);
  if (!limits.enabled || !held || *held < limits.for_s) return std::nullopt;
  return HazardFinding{LatchSource::tilt,
                       fmt::format("roll {:.1f}°, pitch {:.1f}°: beyond {:g}° for {:.2f} s", degrees(sample.roll),
                                   degrees(sample.pitch), limits.max_deg, *held)};
}

void StallHazard::reset() {
  driving_ = false;
  moved_ = false;
  still_since_.reset();
}

std::optional<HazardFinding> StallHazard::judge(const HazardSample& sample, const StallLimits& limits) {
  const bool driving = sample.target != Velocity{};
  if (!driving || !driving_) moved_ = false;  // a drive that just began has not moved yet
  driving_ = driving;
  const double speed = planar_speed(sample.measured);
  const double turn = std::abs(sample.measured.wz);
  if (driving && (speed >= kMovedPlanar || turn >= kMovedTurn)) moved_ = true;
  const bool still = speed < kStillPlanar && turn < kStillTurn;
  const bool asked = planar_speed(sample.sent) >= kAskedPlanar || std::abs(sample.sent.wz) >= kAskedTurn;
  const auto held = held_for(still_since_, moved_ && still && asked, sample.time);
  if (!limits.enabled || !held || *held < limits.for_s) return std::nullopt;
  return HazardFinding{LatchSource::stall,
                       fmt::format("no motion for {:.1f} s while the command asked for vx {:.2f} m/s, vy {:.2f} m/s, "
                                   "wz {:.2f} rad/s",
                                   *held, sample.sent.vx, sample.sent.vy, sample.sent.wz)};
}

std::optional<HazardFinding> HazardJudge::judge(const HazardSample& sample, bool latched) {
  // Every hazard sees every record, so that each one's history is whole when it matters.
  std::optional<HazardFinding> collision = collision_.judge(sample, limits_.collision);
  std::optional<HazardFinding> tilt = tilt_.judge(sample, limits_.tilt);
  std::optional<HazardFinding> stall = stall_.judge(sample, limits_.stall);
  if (latched) return std::nullopt;
  if (collision) return collision;
  if (tilt) return tilt;
  return stall;
}

void HazardJudge::reset() {
  collision_.reset();
  tilt_.reset();
  stall_.reset();
}

}  // namespace wheeltec
