#include "channels.hpp"

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <gtest/gtest.h>

#include "schema_check.hpp"

namespace wheeltec::record {
namespace {

using test::foxglove_problems;
using test::schema_problems;
using Problems = std::vector<std::string>;

Json schema_of(Channel channel) { return Json::parse(channel_spec(channel).schema); }

// The results of docs/api.md's examples (`<- ` lines) that are whole JSON.
std::vector<Json> documented_results() {
  std::ifstream file(WHEELTEC_API_DOC);
  EXPECT_TRUE(file) << WHEELTEC_API_DOC;
  std::vector<Json> results;
  std::string line;
  while (std::getline(file, line)) {
    if (line.rfind("<- ", 0) != 0) continue;
    const Json message = Json::parse(line.substr(3), nullptr, false);
    if (!message.is_discarded() && message.contains("result")) results.push_back(message["result"]);
  }
  return results;
}

std::vector<Json> documented(const char* telling_key) {
  std::vector<Json> found;
  for (const Json& result : documented_results()) {
    if (result.is_object() && result.contains(telling_key)) found.push_back(result);
  }
  return found;
}

Json record(double time, double x, double y, double yaw) {
  return {{"seq", 7}, {"time", time}, {"odom", {{"x", x}, {"y", y}, {"yaw", yaw}}}};
}

TEST(RecordChannels, AreTheFiveOfTheSpecsTable) {
  const auto& all = channels();
  const std::vector<std::pair<std::string_view, std::string_view>> expected{
      {"/telemetry", "wheeltec.Telemetry"}, {"/status", "wheeltec.Status"},        {"/events", "wheeltec.Event"},
      {"/odom", "foxglove.PoseInFrame"},    {"/tf", "foxglove.FrameTransform"}};
  ASSERT_EQ(all.size(), expected.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].topic, expected[i].first);
    EXPECT_EQ(all[i].schema_name, expected[i].second);
    EXPECT_EQ(&channel_spec(all[i].channel), &all[i]);
  }
  EXPECT_EQ(kMessageEncoding, "json");
  EXPECT_EQ(kSchemaEncoding, "jsonschema");
}

TEST(RecordChannels, SchemasAreJsonSchemaDocumentsTitledByTheirName) {
  for (const ChannelSpec& spec : channels()) {
    const Json schema = Json::parse(spec.schema, nullptr, false);
    ASSERT_FALSE(schema.is_discarded()) << spec.schema_name;
    EXPECT_EQ(schema.value("$schema", ""), "https://json-schema.org/draft/2020-12/schema") << spec.schema_name;
    EXPECT_EQ(schema.value("title", ""), spec.schema_name);
  }
}

TEST(RecordChannels, SchemasAreOnesFoxgloveCanRead) {
  for (const ChannelSpec& spec : channels()) {
    EXPECT_EQ(foxglove_problems(Json::parse(spec.schema)), Problems{}) << spec.schema_name;
  }
}

TEST(RecordChannels, TheDocumentedTelemetryRecordsAreValidTelemetry) {
  const std::vector<Json> records = documented("seq");
  ASSERT_FALSE(records.empty());
  for (const Json& each : records) EXPECT_EQ(schema_problems(schema_of(Channel::telemetry), each), Problems{});
  // Every member the schema requires is one the documented record has, and no more.
  Json bare = records.front();
  bare.erase("orientation");
  EXPECT_EQ(schema_problems(schema_of(Channel::telemetry), bare), Problems{"$ lacks orientation"});
}

TEST(RecordChannels, TheDocumentedStatusIsAValidStatus) {
  const std::vector<Json> statuses = documented("uptime_s");
  ASSERT_FALSE(statuses.empty());
  for (const Json& each : statuses) {
    if (!each.contains("bus")) continue;  // stats has uptime_s too
    EXPECT_EQ(schema_problems(schema_of(Channel::status), each), Problems{}) << each.dump();
  }
  Json serial = statuses.front();
  serial["bus"] = Json::parse(R"({"interface":"/dev/wheeltec_controller","state":"up","transport":"serial"})");
  serial["chassis"].erase("dialect");
  serial["dock"] = Json::parse(R"({"present":true,"charging":false,"ir":[true,false,false,true]})");
  EXPECT_EQ(schema_problems(schema_of(Channel::status), serial), Problems{});
}

TEST(RecordChannels, EveryKindOfEventIsAValidEvent) {
  const Json schema = schema_of(Channel::events);
  EXPECT_EQ(schema["properties"]["event"]["enum"].size(), 10u);
  for (const char* text : {
           R"({"time":1795552460.482002,"event":"connected","client":3,"uid":1000,"gid":1000,"pid":4242})",
           R"({"time":1795552460.5,"event":"disconnected","client":3})",
           R"({"time":1795552460.5,"event":"drive","client":3,"vx":0.2,"vy":0.0,"wz":-0.5,"clamped":false})",
           R"({"time":1795552460.5,"event":"refused","client":4,"method":"drive","code":-32001,"message":"control held"})",
           R"({"time":1795552460.5,"event":"stop","client":3})",
           R"({"time":1795552460.5,"event":"deadman","client":3,"after_s":0.512})",
           R"({"time":1795552460.5,"event":"enable","client":3})",
           R"({"time":1795552460.5,"event":"disable","client":3})",
           R"({"time":1795552460.5,"event":"mark","client":5,"text":"bumped the door"})",
           R"({"time":1795552460.5,"event":"reload","client":0,"ok":false,"message":"control.rate_hz: too high"})",
       }) {
    EXPECT_EQ(schema_problems(schema, Json::parse(text)), Problems{}) << text;
  }
  EXPECT_NE(schema_problems(schema, Json::parse(R"({"time":1.0,"event":"jump","client":3})")), Problems{});
}

TEST(RecordChannels, OdomIsThePoseOfTheRecordInTheOdomFrame) {
  const auto pose = odom_pose_in_frame(record(1795552460.482002, 0.401572, -0.25, std::numbers::pi / 2));
  ASSERT_TRUE(pose);
  EXPECT_EQ(schema_problems(schema_of(Channel::odom), *pose), Problems{});
  EXPECT_EQ((*pose)["timestamp"], Json::parse(R"({"sec":1795552460,"nsec":482002000})"));
  EXPECT_EQ((*pose)["frame_id"], "odom");
  EXPECT_EQ((*pose)["pose"]["position"], Json::parse(R"({"x":0.401572,"y":-0.25,"z":0.0})"));
  const Json& q = (*pose)["pose"]["orientation"];
  EXPECT_EQ(q["x"], 0.0);
  EXPECT_EQ(q["y"], 0.0);
  EXPECT_DOUBLE_EQ(q["z"].get<double>(), std::sqrt(0.5));
  EXPECT_DOUBLE_EQ(q["w"].get<double>(), std::sqrt(0.5));
}

TEST(RecordChannels, TfPlacesTheBaseInTheOdomFrameWithTheSamePose) {
  const Json from = record(1795552460.999999, 1.5, 2.5, -std::numbers::pi / 3);
  const auto transform = odom_frame_transform(from);
  ASSERT_TRUE(transform);
  EXPECT_EQ(schema_problems(schema_of(Channel::tf), *transform), Problems{});
  EXPECT_EQ((*transform)["timestamp"], Json::parse(R"({"sec":1795552460,"nsec":999999000})"));
  EXPECT_EQ((*transform)["parent_frame_id"], "odom");
  EXPECT_EQ((*transform)["child_frame_id"], "base_footprint");
  const Json pose = *odom_pose_in_frame(from);
  EXPECT_EQ((*transform)["translation"], pose["pose"]["position"]);
  EXPECT_EQ((*transform)["rotation"], pose["pose"]["orientation"]);
  EXPECT_DOUBLE_EQ((*transform)["rotation"]["z"].get<double>(), -0.5);
}

TEST(RecordChannels, ARecordWithoutTimeOrOdomMakesNoPose) {
  Json no_odom = record(1.0, 0, 0, 0);
  no_odom.erase("odom");
  Json no_time = record(1.0, 0, 0, 0);
  no_time.erase("time");
  Json bad_yaw = record(1.0, 0, 0, 0);
  bad_yaw["odom"]["yaw"] = "north";
  for (const Json& bad : {no_odom, no_time, bad_yaw, Json(), Json::array()}) {
    EXPECT_EQ(odom_pose_in_frame(bad), std::nullopt) << bad.dump();
    EXPECT_EQ(odom_frame_transform(bad), std::nullopt) << bad.dump();
  }
}

}  // namespace
}  // namespace wheeltec::record
