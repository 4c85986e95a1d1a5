// wheeltec-ros2: one robot's wheeltecd as ROS 2 topics over DDS (spec section 9).
// Exit codes: 0 on a clean stop, 2 on bad usage or configuration, 1 on other failures.

#include "wheeltec/service/program.hpp"

#include "bridge.hpp"
#include "options.hpp"

int main(int argc, char** argv) {
  using namespace wheeltec::ros2;
  return wheeltec::service::run_bridge<Bridge>("wheeltec-ros2", argc, argv, parse_command_line, load_config);
}
