#pragma once

#include <string>

namespace wheeltec::service {

// Log records go to the systemd journal (with their priority) when stderr is connected to
// it, which systemd announces in JOURNAL_STREAM; to stderr otherwise, as "program[level]: ".
void setup_logging(const std::string& level, const std::string& program);

// level: trace, debug, info, warn, error (log.level).
void set_log_level(const std::string& level);

}  // namespace wheeltec::service
