#pragma once

#include <string>

namespace wheeltec::daemon {

// Log lines go to stderr (journald adds the time stamps under systemd).
void setup_logging(const std::string& level);

// level: trace, debug, info, warn, error (log.level).
void set_log_level(const std::string& level);

}  // namespace wheeltec::daemon
