// wheeltec-mqtt: bridges one robot's wheeltecd to an MQTT broker (spec section 7).
// Exit codes: 0 on a clean stop, 2 on bad usage or configuration, 1 on other failures.

#include "wheeltec/service/program.hpp"

#include "bridge.hpp"
#include "options.hpp"

int main(int argc, char** argv) {
  using namespace wheeltec::mqtt;
  return wheeltec::service::run_bridge<Bridge>("wheeltec-mqtt", argc, argv, parse_command_line, load_config);
}
