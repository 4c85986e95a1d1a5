#pragma once

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "wheeltec/config/config.hpp"

#include "peer_credentials.hpp"

namespace wheeltec::daemon {

// Who may drive, enable and disable (spec "Control rules"): root, the daemon's own user,
// the users of api.control_users and members of api.control_groups. Everyone else may
// read and stop.
class ControlPolicy {
 public:
  // Resolves the names of api.control_users / api.control_groups; an unknown name is a
  // ConfigError naming the key.
  ControlPolicy(const GatewayConfig::Api& api, uid_t daemon_uid);

  // Why this peer may not control the chassis; empty when it may.
  std::optional<std::string> refusal(const PeerCredentials& peer) const;

 private:
  uid_t daemon_uid_;
  std::vector<uid_t> users_;
  std::vector<gid_t> groups_;
};

}  // namespace wheeltec::daemon
