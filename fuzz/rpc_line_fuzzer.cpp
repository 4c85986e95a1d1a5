// The daemon's JSON-RPC line handling on arbitrary bytes: the input is split into lines
// as a client's stream would be, each line is parsed, its params checked the way every
// method does, and the reply encoded. Any crash, sanitizer report, or a reply that is not
// one valid JSON line is a bug.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>
#include <variant>

#include <nlohmann/json.hpp>

#include "wheeltec/api/rpc.hpp"
#include "wheeltec/types.hpp"

namespace {

namespace rpc = wheeltec::rpc;

void check_reply_line(const std::string& line) {
  if (line.empty() || line.back() != '\n' || line.find('\n') != line.size() - 1) std::abort();
  const auto reply = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (!reply.is_object() || reply.value("jsonrpc", "") != "2.0") std::abort();
}

void handle_line(std::string_view line) {
  if (line.size() > rpc::kMaxLineBytes) return;  // the session refuses these before parsing
  const auto parsed = rpc::parse_request(line);
  if (const auto* error = std::get_if<rpc::Error>(&parsed)) {
    if (error->code != rpc::kParseError && error->code != rpc::kInvalidRequest) std::abort();
    check_reply_line(rpc::encode_error(*error));
    return;
  }
  const auto& request = std::get<rpc::Request>(parsed);
  if (request.is_notification && !request.id.is_null()) std::abort();
  for (const auto chassis : {wheeltec::ChassisType::mecanum, wheeltec::ChassisType::diff}) {
    const auto drive = rpc::parse_drive_params(request, chassis);
    if (const auto* velocity = std::get_if<wheeltec::Velocity>(&drive)) {
      check_reply_line(rpc::encode_result(request.id, {{"vx", velocity->vx}, {"vy", velocity->vy}, {"wz", velocity->wz}}));
    } else {
      const auto& error = std::get<rpc::Error>(drive);
      if (error.code != rpc::kInvalidParams) std::abort();
      check_reply_line(rpc::encode_error(error));
    }
  }
  if (const auto error = rpc::expect_no_params(request)) check_reply_line(rpc::encode_error(*error));
  const auto topics = rpc::parse_topics(request);
  if (const auto* names = std::get_if<std::vector<std::string>>(&topics)) {
    check_reply_line(rpc::encode_result(request.id, {{"topics", *names}}));
  }
  check_reply_line(rpc::encode_notification(request.method, request.params));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string_view input(reinterpret_cast<const char*>(data), size);
  while (!input.empty()) {
    const auto end = input.find('\n');
    handle_line(input.substr(0, end));
    if (end == std::string_view::npos) break;
    input.remove_prefix(end + 1);
  }
  return 0;
}
