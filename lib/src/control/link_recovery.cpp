#include "wheeltec/control/link_recovery.hpp"

#include <algorithm>
#include <utility>

namespace wheeltec {

std::string_view to_string(LinkDownCause cause) {
  for (const auto& entry : kLinkDownCauseNames) {
    if (entry.value == cause) return entry.name;
  }
  return "io-error";
}

bool LinkRecovery::down(LinkDownCause cause) {
  const bool news = cause_ != cause;
  cause_ = cause;
  return news;
}

std::chrono::milliseconds LinkRecovery::next_retry() {
  const std::chrono::milliseconds delay = next_retry_;
  next_retry_ = std::min(next_retry_ * 2, std::max(policy_.max, policy_.first));
  return delay;
}

std::optional<LinkDownCause> LinkRecovery::opened() {
  next_retry_ = policy_.first;
  return std::exchange(cause_, std::nullopt);
}

}  // namespace wheeltec
