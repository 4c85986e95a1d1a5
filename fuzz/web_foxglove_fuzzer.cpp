// wheeltec-web's handling of what any WebSocket client may send: a text message parsed as a
// Foxglove client operation, a binary one as a client publish, and its payload as a
// cmd_vel. Any crash, sanitizer report or exception, a velocity that is not finite, or a
// status message (which may quote the client) that is not valid JSON is a bug.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <variant>

#include "foxglove.hpp"

namespace {

namespace foxglove = wheeltec::web::foxglove;

void check_status_quoting(const std::string& problem) {
  const auto status = foxglove::Json::parse(foxglove::status(foxglove::Level::error, problem, "protocol"), nullptr,
                                            /*allow_exceptions=*/false);
  if (status.is_discarded() || status.value("op", "") != "status") std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const foxglove::ClientMessage message = foxglove::parse_text(input);
  if (const auto* error = std::get_if<foxglove::ProtocolError>(&message)) check_status_quoting(error->message);

  const auto publish = foxglove::parse_binary(input);
  if (const auto* frame = std::get_if<foxglove::ClientPublish>(&publish)) {
    if (frame->payload.size() + 5 != input.size()) std::abort();
  }
  const auto velocity = foxglove::parse_cmd_vel(input);
  if (const auto* v = std::get_if<wheeltec::client::Velocity>(&velocity)) {
    if (!std::isfinite(v->vx) || !std::isfinite(v->vy) || !std::isfinite(v->wz)) std::abort();
  } else {
    check_status_quoting(std::get<foxglove::ProtocolError>(velocity).message);
  }
  return 0;
}
