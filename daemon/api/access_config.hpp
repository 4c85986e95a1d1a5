#pragma once

#include <sys/types.h>

#include <optional>

#include "wheeltec/config/config.hpp"

#include "control_policy.hpp"

namespace wheeltec::daemon {

// The api keys that name users and groups, looked up in the system's databases.
struct AccessConfig {
  std::optional<gid_t> socket_group;  // api.group
  ControlPolicy control_policy;       // api.control_users, api.control_groups
};

// Throws ConfigError naming the key when a user or group does not exist.
AccessConfig resolve_access(const GatewayConfig::Api& api, uid_t daemon_uid);

}  // namespace wheeltec::daemon
