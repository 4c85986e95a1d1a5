// wheeltec-mqtt's handling of what any broker client may publish: the topic is matched
// against the robot's command topics, the payload parsed into the daemon's request or
// refused, and the reply encoded. Any crash, sanitizer report, a refused `stop`, a
// refusal with a code the bridge does not use, a drive with a non-number velocity, or a
// reply that is not valid JSON is a bug.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>

#include "command.hpp"
#include "topics.hpp"

namespace {

namespace mqtt = wheeltec::mqtt;

constexpr mqtt::Command kCommands[] = {mqtt::Command::drive,   mqtt::Command::stop,           mqtt::Command::enable,
                                       mqtt::Command::disable, mqtt::Command::reset_odometry, mqtt::Command::estop,
                                       mqtt::Command::release};

void check_reply(const mqtt::Json& reply) {
  const auto parsed = mqtt::Json::parse(reply.dump(), nullptr, /*allow_exceptions=*/false);
  if (parsed.is_discarded() || parsed.value("jsonrpc", "") != "2.0") std::abort();
}

void check_command(mqtt::Command command, std::string_view payload) {
  const mqtt::ParsedCommand parsed = mqtt::parse_command(command, payload);
  if (const auto* refusal = std::get_if<mqtt::CommandRefusal>(&parsed)) {
    if (command == mqtt::Command::stop || command == mqtt::Command::estop) std::abort();  // never refused
    if (refusal->code != mqtt::kParseError && refusal->code != mqtt::kInvalidRequest &&
        refusal->code != mqtt::kInvalidParams) {
      std::abort();
    }
    check_reply(mqtt::error_reply(command, refusal->id, mqtt::error_object(refusal->code, refusal->message)));
    return;
  }
  const auto& request = std::get<mqtt::CommandRequest>(parsed);
  if (request.command != command) std::abort();
  if (command == mqtt::Command::drive && request.params.is_object()) {
    for (const auto& [key, value] : request.params.items()) {
      if (!value.is_number()) std::abort();
    }
  }
  check_reply(mqtt::result_reply(command, request.id, request.params));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::string_view input(reinterpret_cast<const char*>(data + 1), size - 1);
  // The first byte picks the command; the input is also tried as a topic.
  check_command(kCommands[data[0] % std::size(kCommands)], input);
  static const mqtt::Topics topics("wheeltec", "r1");
  const std::string_view topic = input.substr(0, input.find('\n'));
  const auto command = topics.command_of(topic);
  // A command comes on the robot's own topics, or is the whole fleet's emergency stop.
  const bool fleet_estop = topic == topics.fleet_estop() && command == mqtt::Command::estop;
  if (command && !topics.owns(topic) && !fleet_estop) std::abort();
  return 0;
}
