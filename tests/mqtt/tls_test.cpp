// wheeltec-mqtt over TLS with a client certificate (broker.tls, docs/fleet.md), against a
// real mosquitto that requires one; the certificates are made with openssl for the test.
// No CAN interface is needed: the bridge runs without a daemon (it keeps retrying
// wheeltecd, and is online for the broker meanwhile).

#include <sys/stat.h>

#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "fleet.hpp"
#include "test_environment.hpp"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

constexpr const char* kOpenssl = "/usr/bin/openssl";

void openssl(const fs::path& directory, const std::vector<std::string>& arguments) {
  const auto done = integration::run_program(kOpenssl, arguments, directory, 30s);
  if (!done.status.exited_with(0)) throw std::runtime_error("openssl failed: " + done.describe());
}

// NAME.key and NAME.crt in `directory`, signed by its ca.crt, with the extensions `extensions`.
void make_certificate(const fs::path& directory, const std::string& name, const std::string& subject,
                      const std::string& extensions) {
  const auto file = [&](const char* suffix) { return (directory / (name + suffix)).string(); };
  openssl(directory, {"req", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes", "-keyout",
                      file(".key"), "-out", file(".csr"), "-subj", subject});
  std::ofstream(file(".ext")) << extensions << "\n";
  openssl(directory, {"x509", "-req", "-in", file(".csr"), "-CA", (directory / "ca.crt").string(), "-CAkey",
                      (directory / "ca.key").string(), "-CAcreateserial", "-out", file(".crt"), "-days", "2",
                      "-extfile", file(".ext")});
}

class MqttTls : public ::testing::Test {
 protected:
  void SetUp() override {
    const fs::path& dir = directory_.path();
    openssl(dir, {"req", "-x509", "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes", "-keyout",
                  (dir / "ca.key").string(), "-out", (dir / "ca.crt").string(), "-days", "2", "-subj",
                  "/CN=wheeltec test CA"});
    make_certificate(dir, "broker", "/CN=127.0.0.1", "subjectAltName=IP:127.0.0.1");
    make_certificate(dir, "r1", "/CN=r1", "extendedKeyUsage=clientAuth");
    make_certificate(dir, "alice", "/CN=alice", "extendedKeyUsage=clientAuth");
    ::chmod(dir.c_str(), 0755);  // mosquitto may read its files as the user mosquitto
    for (const char* key : {"broker.key", "r1.key", "alice.key"}) ::chmod((dir / key).c_str(), 0644);
    broker_ = std::make_unique<fleet::Broker>(
        dir,
        std::vector<std::string>{"cafile " + (dir / "ca.crt").string(), "certfile " + (dir / "broker.crt").string(),
                                 "keyfile " + (dir / "broker.key").string(), "require_certificate true",
                                 "use_identity_as_username true"},
        std::vector<std::string>{"--cafile", (dir / "ca.crt").string(), "--cert", (dir / "alice.crt").string(),
                                 "--key", (dir / "alice.key").string()});
    broker_->start();
  }

  void TearDown() override {
    if (HasFailure()) {
      std::cerr << broker_->logs();
      if (bridge_) std::cerr << bridge_->output_report();
    }
    bridge_.reset();
    broker_.reset();
  }

  void start_bridge(const fleet::Json& tls) {
    const fs::path config = directory_.path() / "wheeltec-mqtt.json";
    std::ofstream(config) << fleet::Json{{"robot", "r1"},
                                         {"broker",
                                          {{"host", "127.0.0.1"},
                                           {"port", broker_->port()},
                                           {"reconnect_min_s", 0.2},
                                           {"reconnect_max_s", 1},
                                           {"tls", tls}}}}
                                 .dump(2);
    ::chmod(config.c_str(), 0600);
    bridge_ = std::make_unique<integration::ChildProcess>(
        "wheeltec-mqtt", fleet::bridge_program(),
        std::vector<std::string>{"--config", config.string(), "--socket", (directory_.path() / "no-daemon.sock").string()},
        directory_.path());
  }

  std::string file(const char* name) const { return (directory_.path() / name).string(); }

  integration::TestDirectory directory_;
  std::unique_ptr<fleet::Broker> broker_;
  std::unique_ptr<integration::ChildProcess> bridge_;
};

TEST_F(MqttTls, ABridgeWithItsClientCertificateIsOnlineOverTls) {
  fleet::Subscription online(*broker_, directory_.path(), {"wheeltec/r1/online"});
  start_bridge({{"ca_file", file("ca.crt")}, {"cert_file", file("r1.crt")}, {"key_file", file("r1.key")}});
  const auto seen = online.wait_for(1, "", 15s);
  ASSERT_EQ(seen.size(), 1u) << "the bridge did not come online over TLS";
  EXPECT_EQ(seen[0].payload, "true");
  EXPECT_TRUE(bridge_->running());
}

TEST_F(MqttTls, ABridgeWithoutAClientCertificateIsRefusedAndKeepsTrying) {
  fleet::Subscription online(*broker_, directory_.path(), {"wheeltec/r1/online"});
  start_bridge({{"ca_file", file("ca.crt")}});
  EXPECT_TRUE(online.wait_for(1, "", 3s).empty()) << "a bridge without a certificate got in";
  EXPECT_TRUE(bridge_->running()) << "the bridge gave up instead of retrying";
  EXPECT_NE(bridge_->standard_error().find("no connection to the broker"), std::string::npos)
      << bridge_->standard_error();
}

}  // namespace
