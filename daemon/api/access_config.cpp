#include "access_config.hpp"

#include <fmt/format.h>

#include "user_lookup.hpp"

namespace wheeltec::daemon {

AccessConfig resolve_access(const GatewayConfig::Api& api, uid_t daemon_uid) {
  std::optional<gid_t> socket_group;
  if (api.group) {
    socket_group = lookup_group(*api.group);
    if (!socket_group) throw ConfigError(fmt::format("api.group: unknown group \"{}\"", *api.group));
  }
  return AccessConfig{socket_group, ControlPolicy(api, daemon_uid)};
}

}  // namespace wheeltec::daemon
