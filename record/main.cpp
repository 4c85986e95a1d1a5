// wheeltec-record: the black box of a WHEELTEC robot (spec section 10).
// Exit codes: 0 on a clean stop, 2 on bad usage or configuration (a --dir it cannot write
// included), 1 on other failures.

#include "wheeltec/service/program.hpp"

#include "options.hpp"
#include "recorder.hpp"

int main(int argc, char** argv) {
  using namespace wheeltec::record;
  return wheeltec::service::run_bridge<Recorder>("wheeltec-record", argc, argv, parse_command_line, load_config);
}
