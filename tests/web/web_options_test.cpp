// wheeltec-web's configuration as load_config() layers it: the config file, then the flags.

#include "options.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace wheeltec::web {
namespace {

class WebOptions : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() / ("wheeltec-web-options-" + std::to_string(::getpid()));
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::string config_file(const std::string& text) {
    const auto path = directory_ / "wheeltec-web.json";
    std::ofstream(path) << text;
    return path.string();
  }

  static std::string error_of(const Options& options) {
    try {
      load_config(options);
    } catch (const ConfigError& error) {
      return error.what();
    }
    return "(accepted)";
  }

  std::filesystem::path directory_;
};

TEST_F(WebOptions, ATlsPairMaySplitBetweenTheFileAndTheFlags) {
  Options options;
  options.config_file = config_file(R"({"tls": {"cert": "/etc/wheeltec-web/cert.pem"}})");
  options.tls_key = "/etc/wheeltec-web/key.pem";
  const WebConfig config = load_config(options);
  EXPECT_EQ(config.tls.cert, "/etc/wheeltec-web/cert.pem");
  EXPECT_EQ(config.tls.key, "/etc/wheeltec-web/key.pem");

  options.config_file = config_file(R"({"tls": {"key": "/etc/wheeltec-web/key.pem"}})");
  options.tls_key.reset();
  options.tls_cert = "/etc/wheeltec-web/cert.pem";
  EXPECT_EQ(error_of(options), "(accepted)");
}

TEST_F(WebOptions, AHalfPairIsNamedWhereItComesFrom) {
  Options from_file;
  from_file.config_file = config_file(R"({"tls": {"cert": "/etc/wheeltec-web/cert.pem"}})");
  EXPECT_EQ(error_of(from_file),
            *from_file.config_file + ": tls.key: tls.cert and tls.key go together: give both or neither");

  Options from_flags;
  from_flags.config_file = config_file("{}");
  from_flags.tls_cert = "/etc/wheeltec-web/cert.pem";
  EXPECT_EQ(error_of(from_flags), "command line: tls.key: tls.cert and tls.key go together: give both or neither");
}

TEST_F(WebOptions, FlagsOverrideTheFileAndAreCheckedAsItIs) {
  Options options;
  options.config_file = config_file(R"({"log": {"level": "warning"}, "listen": "0.0.0.0:9000"})");
  options.log_level = "debug";
  const WebConfig config = load_config(options);
  EXPECT_EQ(config.log.level, "debug");
  EXPECT_EQ(config.listen.port, 9000);

  options.log_level.reset();
  EXPECT_EQ(error_of(options).rfind(*options.config_file + ": log.level: must be one of", 0), 0u) << error_of(options);

  Options long_socket;
  long_socket.config_file = config_file("{}");
  long_socket.socket = "/" + std::string(120, 's');
  EXPECT_EQ(error_of(long_socket).rfind("command line: socket: must be shorter than 108 bytes", 0), 0u);
}

TEST_F(WebOptions, TheRecordDirectoryComesFromTheFileOrTheFlagAndIsAbsolute) {
  Options options;
  options.config_file = config_file(R"({"record_dir": "/srv/records"})");
  EXPECT_EQ(load_config(options).record_dir, "/srv/records");
  options.record_dir = "/tmp/records";
  EXPECT_EQ(load_config(options).record_dir, "/tmp/records");
  options.record_dir = "records";
  EXPECT_EQ(error_of(options), "command line: record_dir: must be an absolute path, got \"records\"");
}

}  // namespace
}  // namespace wheeltec::web
