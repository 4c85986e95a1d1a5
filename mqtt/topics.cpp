#include "topics.hpp"

#include <array>
#include <cstdint>

namespace wheeltec::mqtt {
namespace {

constexpr std::size_t kMaxNameBytes = 1024;  // far below MQTT's 65535-byte topics

bool is_valid_utf8(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size()) {
    const auto lead = static_cast<std::uint8_t>(text[i]);
    std::size_t length = 1;
    if (lead >= 0xF0 && lead <= 0xF4) length = 4;
    else if (lead >= 0xE0) length = 3;
    else if (lead >= 0xC2 && lead <= 0xDF) length = 2;
    else if (lead >= 0x80) return false;
    if (i + length > text.size()) return false;
    for (std::size_t k = 1; k < length; ++k) {
      if ((static_cast<std::uint8_t>(text[i + k]) & 0xC0) != 0x80) return false;
    }
    i += length;
  }
  return true;
}

std::optional<std::string> level_problem(std::string_view level) {
  if (level.empty()) return "has an empty topic level";
  for (const char c : level) {
    if (c == '+' || c == '#') return std::string("holds the MQTT wildcard '") + c + "'";
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) return "holds a control character";
  }
  return std::nullopt;
}

std::optional<std::string> levels_problem(std::string_view text) {
  if (text.empty()) return "is empty";
  if (text.size() > kMaxNameBytes) return "is longer than " + std::to_string(kMaxNameBytes) + " bytes";
  if (!is_valid_utf8(text)) return "is not valid UTF-8";
  if (text.front() == '$') return "starts with '$' (topics of the broker itself)";
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = text.find('/', start);
    const std::string_view level = text.substr(start, slash == std::string_view::npos ? text.npos : slash - start);
    if (auto problem = level_problem(level)) return problem;
    if (slash == std::string_view::npos) return std::nullopt;
    start = slash + 1;
  }
}

}  // namespace

std::string_view command_name(Command command) {
  switch (command) {
    case Command::drive: return "drive";
    case Command::stop: return "stop";
    case Command::enable: return "enable";
    case Command::disable: return "disable";
    case Command::reset_odometry: return "reset_odometry";
    case Command::estop: return "estop";
    case Command::release: return "release";
  }
  return "?";
}

std::optional<std::string> prefix_problem(std::string_view prefix) { return levels_problem(prefix); }

std::optional<std::string> robot_name_problem(std::string_view robot) {
  if (robot.find('/') != std::string_view::npos) return "holds '/' (a robot name is one topic level)";
  if (robot == kFleetName) {
    return "\"" + std::string(kFleetName) + "\" is reserved: PREFIX/" + std::string(kFleetName) +
           "/cmd/estop is the whole fleet's emergency stop";
  }
  return levels_problem(robot);
}

Topics::Topics(std::string_view prefix, std::string_view robot)
    : base_(std::string(prefix) + "/" + std::string(robot)),
      telemetry_(base_ + "/telemetry"),
      status_(base_ + "/status"),
      online_(base_ + "/online"),
      stats_(base_ + "/stats"),
      result_(base_ + "/cmd/result"),
      fleet_estop_(std::string(prefix) + "/" + std::string(kFleetName) + "/cmd/estop") {
  for (const Command each : kCommands) command_topics_.push_back(command(each));
  command_topics_.push_back(fleet_estop_);
}

std::string Topics::command(Command command) const { return base_ + "/cmd/" + std::string(command_name(command)); }

std::optional<Command> Topics::command_of(std::string_view topic) const {
  if (topic == fleet_estop_) return Command::estop;
  const std::string head = base_ + "/cmd/";
  if (topic.substr(0, head.size()) != head) return std::nullopt;
  const std::string_view name = topic.substr(head.size());
  for (const Command command : kCommands) {
    if (name == command_name(command)) return command;
  }
  return std::nullopt;
}

bool Topics::owns(std::string_view topic) const {
  return topic != result_ && topic.size() > base_.size() && topic.substr(0, base_.size()) == base_ &&
         topic[base_.size()] == '/';
}

}  // namespace wheeltec::mqtt
