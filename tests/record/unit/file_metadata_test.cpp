#include "file_metadata.hpp"

#include <gtest/gtest.h>

#include "test_time.hpp"

namespace wheeltec::record {
namespace {

using std::chrono::microseconds;
using std::chrono::seconds;

using test::t0;

TEST(RecordFileMetadata, NamesTheDaemonLinkAndChassisOfTheStatus) {
  const Json status = Json::parse(R"({"bus":{"interface":"vcan0","state":"up","transport":"can"},
      "chassis":{"type":"mecanum","online":true},"version":"0.4.0","uptime_s":3.0})");
  const std::vector<FiredTrigger> triggers{{Trigger::deadman, t0 + microseconds(482'002)},
                                           {Trigger::link_down, t0 + seconds(4)}};
  const auto metadata = file_metadata(status, triggers);
  EXPECT_EQ(metadata, (std::map<std::string, std::string>{
                          {"version", "0.4.0"},
                          {"transport", "can"},
                          {"device", "vcan0"},
                          {"chassis", "mecanum"},
                          {"triggers", R"([{"trigger":"deadman","time":1795552460.482002},)"
                                       R"({"trigger":"link-down","time":1795552464.000000}])"},
                      }));
  const Json parsed = Json::parse(metadata.at("triggers"));
  EXPECT_EQ(parsed[1]["trigger"], "link-down");
  EXPECT_DOUBLE_EQ(parsed[0]["time"].get<double>(), 1795552460.482002);
}

TEST(RecordFileMetadata, SerialLinkNamesItsDevice) {
  const Json status = Json::parse(R"({"bus":{"interface":"/dev/wheeltec_controller","state":"down",
      "transport":"serial"},"chassis":{"type":"diff"},"version":"0.4.0"})");
  const auto metadata = file_metadata(status, {{Trigger::mark, t0}});
  EXPECT_EQ(metadata.at("transport"), "serial");
  EXPECT_EQ(metadata.at("device"), "/dev/wheeltec_controller");
  EXPECT_EQ(metadata.at("triggers"), R"([{"trigger":"mark","time":1795552460.000000}])");
}

TEST(RecordFileMetadata, WithoutAStatusTheDaemonsKeysAreEmpty) {
  const auto metadata = file_metadata(Json(), {{Trigger::daemon_lost, t0}});
  EXPECT_EQ(metadata.at("version"), "");
  EXPECT_EQ(metadata.at("transport"), "");
  EXPECT_EQ(metadata.at("device"), "");
  EXPECT_EQ(metadata.at("chassis"), "");
  EXPECT_EQ(metadata.size(), 5u);
  EXPECT_EQ(triggers_json({}), "[]");
}

}  // namespace
}  // namespace wheeltec::record
