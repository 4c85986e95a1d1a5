#pragma once

// The bridge's MQTT topics under PREFIX/ROBOT (spec section 7), and the rules that keep a
// prefix or robot name from reaching into other robots' topics.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace wheeltec::mqtt {

enum class Command { drive, stop, enable, disable, reset_odometry, estop, release };
inline constexpr std::array kCommands{Command::drive,          Command::stop,  Command::enable, Command::disable,
                                      Command::reset_odometry, Command::estop, Command::release};

// The robot name whose topics belong to the whole fleet: PREFIX/all/cmd/estop, which every
// bridge subscribes, so no robot may be called so.
inline constexpr std::string_view kFleetName = "all";

// The topic level of a command ("reset_odometry"), which is also the daemon's method name.
std::string_view command_name(Command command);

// Why `prefix` cannot be a topic prefix, or empty when it can: one or more levels
// separated by '/', none empty, none holding the wildcards '+' or '#' or a control
// character, valid UTF-8, not starting with '$' (the broker's own topics).
std::optional<std::string> prefix_problem(std::string_view prefix);
// Why `robot` cannot be a robot name: as a prefix, a single level (no '/'), and not
// kFleetName.
std::optional<std::string> robot_name_problem(std::string_view robot);

class Topics {
 public:
  // Both must have passed the checks above.
  Topics(std::string_view prefix, std::string_view robot);

  const std::string& telemetry() const { return telemetry_; }
  const std::string& status() const { return status_; }
  const std::string& online() const { return online_; }
  const std::string& stats() const { return stats_; }
  // Where results go when the command carried no MQTT 5 response topic.
  const std::string& result() const { return result_; }
  // The topics subscribed to: PREFIX/ROBOT/cmd/COMMAND for each command, and the fleet's
  // PREFIX/all/cmd/estop. Not cmd/+, which covers cmd/result too: the broker would send
  // each of the bridge's replies back to it.
  const std::vector<std::string>& command_topics() const { return command_topics_; }
  // PREFIX/all/cmd/estop: one message stops every robot of the prefix.
  const std::string& fleet_estop() const { return fleet_estop_; }
  std::string command(Command command) const;
  // The command a topic is for; empty for any other topic (cmd/result among them).
  std::optional<Command> command_of(std::string_view topic) const;
  // Whether `topic` lies under PREFIX/ROBOT/, the robot's own topics, cmd/result aside.
  bool owns(std::string_view topic) const;

 private:
  std::string base_;
  std::string telemetry_, status_, online_, stats_, result_, fleet_estop_;
  std::vector<std::string> command_topics_;
};

}  // namespace wheeltec::mqtt
