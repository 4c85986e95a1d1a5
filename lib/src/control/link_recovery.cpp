#include "wheeltec/control/link_recovery.hpp"

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

std::optional<LinkDownCause> LinkRecovery::opened() {
  retries_.reset();
  return std::exchange(cause_, std::nullopt);
}

}  // namespace wheeltec
