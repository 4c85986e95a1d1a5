#include "supervisor_log.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

void log_stage_change(std::optional<ChassisStage> previous, ChassisStage stage) {
  switch (stage) {
    case ChassisStage::booting:
      if (previous) {
        spdlog::warn("chassis controller rebooted (flag_stop set after a telemetry gap): booting");
      } else {
        spdlog::info("chassis phase booting (flag_stop set)");
      }
      break;
    case ChassisStage::self_test_awaited:
      spdlog::info("chassis phase self-test: boot over, watching for the controller's own drive");
      break;
    case ChassisStage::self_test_driving:
      spdlog::warn("chassis self-test: the controller drives forward by itself (2 s at 0.2 m/s, about 0.4 m)");
      break;
    case ChassisStage::ready:
      spdlog::info("chassis phase ready");
      break;
    case ChassisStage::halted:
      spdlog::warn("chassis halted: flag_stop set outside boot (enable switch off, low voltage or a protection)");
      break;
  }
}

void log_command_response(CommandResponse before, CommandResponse now, const GatewayConfig& config) {
  if (now == before) return;
  if (now == CommandResponse::ignored) {
    const double patience = std::chrono::duration<double>(CommandResponseMonitor::kPatience).count();
    if (config.transport == Transport::can) {
      spdlog::warn("the chassis ignores the drive commands: no motion after {:g} s of commanding it with flag_stop "
                   "clear; likely cause: can.dialect ({}) does not match the firmware (try the other dialect)",
                   patience, to_string(config.can.dialect));
    } else {
      spdlog::warn("the chassis ignores the drive commands: no motion after {:g} s of commanding it with flag_stop "
                   "clear; likely cause: the controller does not read commands on this port, or the wheels are "
                   "blocked",
                   patience);
    }
  } else if (before == CommandResponse::ignored) {
    spdlog::info("the chassis {}",
                 now == CommandResponse::followed ? "follows the commands again" : "is no longer commanded to move");
  }
}

}  // namespace wheeltec::daemon
