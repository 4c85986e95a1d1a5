#pragma once

#include <optional>

#include "wheeltec/control/chassis_phase.hpp"
#include "wheeltec/control/command_response.hpp"
#include "wheeltec/config/config.hpp"

namespace wheeltec::daemon {

// What the user reads in the log when the supervisor sees the controller change.
void log_stage_change(std::optional<ChassisStage> previous, ChassisStage stage);
void log_command_response(CommandResponse before, CommandResponse now, const GatewayConfig& config);

}  // namespace wheeltec::daemon
