// How the serial link shows in the API and on the command line (spec section 8): status.bus,
// the protocol (5: the emergency stop), the config keys, the usage error.

#include <gtest/gtest.h>

#include <fstream>

#include "serial_daemon.hpp"

namespace serial_tests {
namespace {

using SerialStatus = SerialTest;

TEST_F(SerialStatus, BusIsTransportSerialWithTheLinkAsConfiguredAndProtocol4) {
  fake_->start_telemetry();
  SerialDaemon& daemon = start_daemon_up();
  auto client = daemon.connect();
  const Json status = client.call("status");
  EXPECT_EQ(status["bus"], Json({{"transport", "serial"}, {"interface", link_.string()}, {"state", "up"}}))
      << "the symlink's path as configured, not " << fake_->slave_name() << ": " << status.dump();
  EXPECT_FALSE(status["chassis"].contains("dialect")) << "the serial line has no dialect: " << status.dump();
  const Json version = client.call("version");
  EXPECT_EQ(version["protocol"], 5) << version.dump();
  ASSERT_TRUE(wait_for_status(client, [](const Json& s) { return s["chassis"]["online"] == true; }, 2s)) << logs();
  const Json record = client.call("telemetry");
  EXPECT_NEAR(record["battery"]["voltage"].get<double>(), 22.5, 1e-9) << record.dump();
  EXPECT_NEAR(record["accel"]["z"].get<double>(), 16403.0 / 1672.0, 1e-4) << record.dump();
}

TEST_F(SerialStatus, TransportSerialFromTheConfigFileAlone) {
  fake_->start_telemetry();
  DaemonOptions options;
  options.serial_flag = false;  // transport and serial.device in the file
  options.config_patch = {{"serial", {{"baud", 115200}}}};
  SerialDaemon& daemon = start_daemon_up(options);
  auto client = daemon.connect();
  const Json status = client.call("status");
  EXPECT_EQ(status["bus"], Json({{"transport", "serial"}, {"interface", link_.string()}, {"state", "up"}}))
      << status.dump();
  ASSERT_TRUE(wait_for_status(client, [](const Json& s) { return s["chassis"]["online"] == true; }, 2s)) << logs();
}

TEST_F(SerialStatus, CheckConfigPrintsTransportAndSerial) {
  const auto config = directory_->path() / "check.json";
  std::ofstream(config) << R"({"serial": {"baud": 115200}})" << "\n";
  const auto result = integration::run_program(integration::program_path("wheeltecd"),
                                               {"--config", config.string(), "--serial", link_.string(), "--check-config"},
                                               directory_->path());
  ASSERT_TRUE(result.status.exited_with(0)) << result.describe();
  const Json merged = Json::parse(result.out, nullptr, /*allow_exceptions=*/false);
  ASSERT_TRUE(merged.is_object()) << result.out;
  EXPECT_EQ(merged["transport"], "serial") << result.out;
  EXPECT_EQ(merged["serial"]["device"], link_.string()) << result.out;
  EXPECT_EQ(merged["serial"]["baud"], 115200) << result.out;

  const auto defaults = integration::run_program(integration::program_path("wheeltecd"),
                                                 {"--config", config.string(), "--check-config"}, directory_->path());
  ASSERT_TRUE(defaults.status.exited_with(0)) << defaults.describe();
  const Json plain = Json::parse(defaults.out, nullptr, false);
  EXPECT_EQ(plain["transport"], "can") << defaults.out;
  EXPECT_EQ(plain["serial"]["device"], "/dev/wheeltec_controller") << defaults.out;
}

TEST_F(SerialStatus, SerialAndInterfaceTogetherIsAUsageError) {
  const auto result = integration::run_program(integration::program_path("wheeltecd"),
                                               {"--serial", link_.string(), "--interface", "vcan0", "--check-config"},
                                               directory_->path());
  EXPECT_TRUE(result.status.exited_with(2)) << result.describe();
  EXPECT_FALSE(result.err.empty()) << "a one-line error on stderr";

  const auto config = directory_->path() / "bad.json";
  std::ofstream(config) << R"({"transport": "usb"})" << "\n";
  const auto bad = integration::run_program(integration::program_path("wheeltecd"),
                                            {"--config", config.string(), "--check-config"}, directory_->path());
  EXPECT_TRUE(bad.status.exited_with(2)) << bad.describe();
  EXPECT_NE(bad.err.find("transport"), std::string::npos) << "the error names the key: " << bad.err;
}

}  // namespace
}  // namespace serial_tests
