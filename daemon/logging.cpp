#include "logging.hpp"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

void setup_logging(const std::string& level) {
  auto logger = spdlog::stderr_logger_st("wheeltecd");
  logger->set_pattern("wheeltecd[%l]: %v");
  spdlog::set_default_logger(std::move(logger));
  set_log_level(level);
}

void set_log_level(const std::string& level) { spdlog::set_level(spdlog::level::from_str(level)); }

}  // namespace wheeltec::daemon
