#pragma once

#include <chrono>
#include <string_view>

#include "wheeltec/types.hpp"

namespace wheeltec {

// Whether the controller runs its own drive after booting (C50X firmware,
// balance_task.c: 2 s forward at 0.2 m/s, 0.3 s zero, then the stored command).
enum class SelfTest { drive, skip };

// Where the emulated controller is in its start-up, by time since power-on.
enum class ControllerPhase {
  booting,          // motors off, flag_stop 1
  self_test_drive,  // forward at kSelfTestSpeed by itself, whatever was commanded
  self_test_stop,   // zero, then the stored command
  running,          // obeys its command
};

inline constexpr std::chrono::nanoseconds kSelfTestDriveTime = std::chrono::seconds(2);
inline constexpr std::chrono::nanoseconds kSelfTestStopTime = std::chrono::milliseconds(300);
inline constexpr double kSelfTestSpeed = 0.2;  // m/s forward

ControllerPhase controller_phase(std::chrono::nanoseconds since_power_on, std::chrono::nanoseconds boot_delay, SelfTest self_test);
// When the controller starts running its command.
std::chrono::nanoseconds running_from(std::chrono::nanoseconds boot_delay, SelfTest self_test);

std::string_view to_string(ControllerPhase phase);

}  // namespace wheeltec
