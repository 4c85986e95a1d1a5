#pragma once

#include <optional>
#include <string_view>

#include "wheeltec/frames/telemetry_record.hpp"

namespace wheeltec {

// How the chassis stands, in radians: roll about x (forward; positive lifts the left
// side), pitch about y (left; positive lowers the nose). Right-handed, z up.
struct ChassisTilt {
  double roll = 0.0;
  double pitch = 0.0;
};

// What a resting accelerometer reads in the body frame (x forward, y left, z up):
// the reaction to gravity, R^T * (0, 0, g) with R = Ry(pitch) * Rx(roll).
Vector3 gravity_reaction(const ChassisTilt& tilt, double gravity);

// "ROLL,PITCH" in degrees, |roll| <= 180, |pitch| <= 90; empty when malformed or out of range.
std::optional<ChassisTilt> parse_tilt_degrees(std::string_view text);

}  // namespace wheeltec
