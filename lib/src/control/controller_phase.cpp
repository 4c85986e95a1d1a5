#include "wheeltec/control/controller_phase.hpp"

namespace wheeltec {

std::chrono::nanoseconds running_from(std::chrono::nanoseconds boot_delay, SelfTest self_test) {
  return self_test == SelfTest::drive ? boot_delay + kSelfTestDriveTime + kSelfTestStopTime : boot_delay;
}

ControllerPhase controller_phase(std::chrono::nanoseconds since_power_on, std::chrono::nanoseconds boot_delay, SelfTest self_test) {
  if (since_power_on < boot_delay) return ControllerPhase::booting;
  if (since_power_on >= running_from(boot_delay, self_test)) return ControllerPhase::running;
  if (since_power_on < boot_delay + kSelfTestDriveTime) return ControllerPhase::self_test_drive;
  return ControllerPhase::self_test_stop;
}

std::string_view to_string(ControllerPhase phase) {
  switch (phase) {
    case ControllerPhase::booting: return "booting";
    case ControllerPhase::self_test_drive: return "self-test drive";
    case ControllerPhase::self_test_stop: return "self-test stop";
    case ControllerPhase::running: return "running";
  }
  return "unknown";
}

}  // namespace wheeltec
