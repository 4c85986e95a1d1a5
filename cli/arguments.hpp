#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "wheeltec/types.hpp"

// Pure interpretation of command-line values (no I/O), kept apart for unit tests.
namespace wheeltecctl {

// --socket, else $WHEELTEC_SOCKET (when set and not empty), else the daemon default.
std::string resolve_socket_path(const std::optional<std::string>& option);

// A finite decimal number, the whole text (leading/trailing spaces rejected).
std::optional<double> parse_finite_number(std::string_view text);

// "VX WZ" or "VX VY WZ". Returns the velocity or a one-line error message.
std::variant<wheeltec::Velocity, std::string> parse_drive_velocity(
    const std::vector<std::string>& positionals);

}  // namespace wheeltecctl
