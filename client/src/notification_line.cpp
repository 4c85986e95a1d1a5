#include "notification_line.hpp"

#include <nlohmann/json.hpp>

namespace wheeltec::client {
namespace {

constexpr std::string_view kPrefix = R"({"jsonrpc":"2.0","method":")";
constexpr std::string_view kParamsKey = R"(","params":)";

std::string_view trim_trailing_space(std::string_view text) {
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r' || text.back() == '\n')) {
    text.remove_suffix(1);
  }
  return text;
}

// Why `line` is not JSON, or empty when it is JSON after all (in some other layout).
std::string parse_failure(std::string_view line) {
  if (nlohmann::json::accept(line.begin(), line.end())) return {};
  try {
    const auto document = nlohmann::json::parse(line.begin(), line.end());
    return document.is_discarded() ? "not JSON" : std::string();
  } catch (const nlohmann::json::exception& error) {
    return error.what();
  }
}

}  // namespace

NotificationRead read_notification(std::string_view line) {
  if (!line.starts_with(kPrefix)) return OtherLayout{};
  const std::string_view after_prefix = line.substr(kPrefix.size());
  const std::size_t method_end = after_prefix.find('"');
  if (method_end == std::string_view::npos) return MalformedLine{"a notification whose method never ends"};
  const std::string_view method = after_prefix.substr(0, method_end);
  if (method.find('\\') != std::string_view::npos) return OtherLayout{};  // escapes: let the parser read it
  const std::string_view after_method = after_prefix.substr(method_end);
  const std::string_view body = trim_trailing_space(after_method);
  if (!body.starts_with(kParamsKey) || !body.ends_with('}')) {
    if (std::string reason = parse_failure(line); !reason.empty()) return MalformedLine{std::move(reason)};
    return OtherLayout{};
  }
  const std::string_view params = body.substr(kParamsKey.size(), body.size() - kParamsKey.size() - 1);
  if (nlohmann::json::accept(params.begin(), params.end())) return DaemonNotification{method, params};
  if (std::string reason = parse_failure(line); !reason.empty()) return MalformedLine{std::move(reason)};
  return OtherLayout{};  // e.g. a member after params: valid, read whole
}

}  // namespace wheeltec::client
