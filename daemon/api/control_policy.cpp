#include "control_policy.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "user_lookup.hpp"

namespace wheeltec::daemon {

ControlPolicy::ControlPolicy(const GatewayConfig::Api& api, uid_t daemon_uid) : daemon_uid_(daemon_uid) {
  for (std::size_t i = 0; i < api.control_users.size(); ++i) {
    const auto uid = lookup_user(api.control_users[i]);
    if (!uid) throw ConfigError(fmt::format("api.control_users[{}]: unknown user \"{}\"", i, api.control_users[i]));
    users_.push_back(*uid);
  }
  for (std::size_t i = 0; i < api.control_groups.size(); ++i) {
    const auto gid = lookup_group(api.control_groups[i]);
    if (!gid) throw ConfigError(fmt::format("api.control_groups[{}]: unknown group \"{}\"", i, api.control_groups[i]));
    groups_.push_back(*gid);
  }
}

std::optional<std::string> ControlPolicy::refusal(const PeerCredentials& peer) const {
  if (peer.uid == 0 || peer.uid == daemon_uid_) return std::nullopt;
  if (std::find(users_.begin(), users_.end(), peer.uid) != users_.end()) return std::nullopt;
  const auto in_groups = [&](gid_t gid) { return std::find(groups_.begin(), groups_.end(), gid) != groups_.end(); };
  if (in_groups(peer.gid) || std::any_of(peer.supplementary.begin(), peer.supplementary.end(), in_groups)) {
    return std::nullopt;
  }
  return fmt::format("uid {} may not control the chassis: not in api.control_users or api.control_groups", peer.uid);
}

}  // namespace wheeltec::daemon
