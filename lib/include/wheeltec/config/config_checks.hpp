#pragma once

// The value checks that more than one program's configuration makes (wheeltecd's and the
// bridges'), each written once. Every problem is a ConfigError naming the key. Pure: no I/O.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "wheeltec/config/config.hpp"  // ConfigError

namespace wheeltec::config_checks {

// sizeof(sockaddr_un::sun_path), the terminating NUL included.
inline constexpr std::size_t kSunPathSize = 108;

// A Unix socket's path: not empty, and shorter than sun_path.
void check_socket_path(const std::string& path, std::string_view key);

// One of kLogLevels.
void check_log_level(const std::string& level, std::string_view key = "log.level");

// A file given by name (null for none) is not given as "".
void check_optional_file(const std::optional<std::string>& file, std::string_view key);

// A certificate and its private key go together: both or neither. Meant for the merged
// configuration (config file and flags), since either may come from either.
void check_certificate_pair(const std::optional<std::string>& cert, std::string_view cert_key,
                            const std::optional<std::string>& private_key, std::string_view private_key_key);

struct HostPort {
  std::string host;  // a name or an address; an IPv6 address without its brackets
  std::uint16_t port;
};

// What the port of a HOST:PORT is for: a server may listen on port 0 (the kernel picks
// one); a client connects to a port in [1, 65535].
enum class PortUse { listen, connect };

// "HOST:PORT", an IPv6 address in brackets ("[::1]:1883").
HostPort parse_host_port(std::string_view text, std::string_view key, PortUse use);

}  // namespace wheeltec::config_checks
