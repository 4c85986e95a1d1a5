#include "wheeltec/config/config_checks.hpp"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "wheeltec/config/config_fields.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec::config_checks {

using config_fields::fail;

void check_socket_path(const std::string& path, std::string_view key) {
  if (path.empty()) fail(key, "must not be empty");
  if (path.size() >= kSunPathSize) {
    fail(key, fmt::format("must be shorter than {} bytes (sun_path), got {} bytes", kSunPathSize, path.size()));
  }
}

void check_log_level(const std::string& level, std::string_view key) {
  if (std::find(kLogLevels.begin(), kLogLevels.end(), level) == kLogLevels.end()) {
    fail(key, fmt::format("must be one of {}, got \"{}\"", fmt::join(kLogLevels, ", "), level));
  }
}

void check_optional_file(const std::optional<std::string>& file, std::string_view key) {
  if (file && file->empty()) fail(key, "must not be empty (null for none)");
}

void check_certificate_pair(const std::optional<std::string>& cert, std::string_view cert_key,
                            const std::optional<std::string>& private_key, std::string_view private_key_key) {
  if (cert.has_value() == private_key.has_value()) return;
  fail(cert ? private_key_key : cert_key,
       fmt::format("{} and {} go together: give both or neither", cert_key, private_key_key));
}

HostPort parse_host_port(std::string_view text, std::string_view key, PortUse use) {
  const auto malformed = [&] { fail(key, fmt::format("expected HOST:PORT, got \"{}\"", text)); };
  const std::size_t colon = text.rfind(':');
  if (colon == std::string_view::npos || colon == 0) malformed();
  std::string_view host = text.substr(0, colon);
  if (host.front() == '[') {
    if (host.size() < 3 || host.back() != ']') fail(key, "an IPv6 address goes in brackets: [::1]:PORT");
    host = host.substr(1, host.size() - 2);
  }
  if (host.find_first_of("[]") != std::string_view::npos) malformed();
  const std::string_view port_text = text.substr(colon + 1);
  const unsigned lowest = use == PortUse::listen ? 0 : 1;
  unsigned port = 0;
  const auto [end, error] = std::from_chars(port_text.data(), port_text.data() + port_text.size(), port);
  if (port_text.empty() || error != std::errc() || end != port_text.data() + port_text.size() || port < lowest ||
      port > 65535) {
    fail(key, fmt::format("port must be an integer in [{}, 65535], got \"{}\"", lowest, port_text));
  }
  return {std::string(host), static_cast<std::uint16_t>(port)};
}

}  // namespace wheeltec::config_checks
