#include "wheeltec/config/config_checks.hpp"

#include <optional>
#include <string>

#include <gtest/gtest.h>

namespace wheeltec::config_checks {
namespace {

template <typename Check>
std::string error_of(Check check) {
  try {
    check();
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "(accepted)";
}

TEST(ConfigChecks, ASocketPathFitsSunPath) {
  EXPECT_EQ(error_of([] { check_socket_path("/run/x.sock", "socket"); }), "(accepted)");
  EXPECT_EQ(error_of([] { check_socket_path(std::string(107, 's'), "socket"); }), "(accepted)");
  EXPECT_EQ(error_of([] { check_socket_path(std::string(108, 's'), "socket"); }),
            "socket: must be shorter than 108 bytes (sun_path), got 108 bytes");
  EXPECT_EQ(error_of([] { check_socket_path("", "api.socket"); }), "api.socket: must not be empty");
}

TEST(ConfigChecks, LogLevelIsOneOfTheFive) {
  for (const char* level : {"trace", "debug", "info", "warn", "error"}) {
    EXPECT_EQ(error_of([&] { check_log_level(level); }), "(accepted)") << level;
  }
  EXPECT_EQ(error_of([] { check_log_level("warning"); }),
            "log.level: must be one of trace, debug, info, warn, error, got \"warning\"");
}

TEST(ConfigChecks, ACertificateAndItsKeyGoTogether) {
  const std::optional<std::string> none;
  const std::optional<std::string> file = "/etc/x.pem";
  EXPECT_EQ(error_of([&] { check_certificate_pair(none, "tls.cert", none, "tls.key"); }), "(accepted)");
  EXPECT_EQ(error_of([&] { check_certificate_pair(file, "tls.cert", file, "tls.key"); }), "(accepted)");
  EXPECT_EQ(error_of([&] { check_certificate_pair(file, "tls.cert", none, "tls.key"); }),
            "tls.key: tls.cert and tls.key go together: give both or neither");
  EXPECT_EQ(error_of([&] { check_certificate_pair(none, "tls.cert", file, "tls.key"); }),
            "tls.cert: tls.cert and tls.key go together: give both or neither");
  EXPECT_EQ(error_of([&] { check_optional_file(std::string(), "tls.key"); }),
            "tls.key: must not be empty (null for none)");
}

TEST(ConfigChecks, HostPortForListeningAndForConnecting) {
  const HostPort a = parse_host_port("127.0.0.1:8080", "--listen", PortUse::listen);
  EXPECT_EQ(a.host, "127.0.0.1");
  EXPECT_EQ(a.port, 8080);
  const HostPort b = parse_host_port("[::1]:0", "--listen", PortUse::listen);
  EXPECT_EQ(b.host, "::1");
  EXPECT_EQ(b.port, 0);
  EXPECT_EQ(parse_host_port("broker.lan:1883", "--broker", PortUse::connect).host, "broker.lan");
  EXPECT_EQ(error_of([] { parse_host_port("broker:0", "--broker", PortUse::connect); }),
            "--broker: port must be an integer in [1, 65535], got \"0\"");
  for (const char* bad : {"8080", ":8080", "host:", "host:65536", "host:80x", "[::1:80", "[]:80", "a]b:80", "h:-1"}) {
    for (const PortUse use : {PortUse::listen, PortUse::connect}) {
      EXPECT_THROW(parse_host_port(bad, "k", use), ConfigError) << bad;
    }
  }
}

}  // namespace
}  // namespace wheeltec::config_checks
