#include "foxglove.hpp"

#include <gtest/gtest.h>

namespace wheeltec::web::foxglove {
namespace {

TEST(Foxglove, AdvertisesTheFourChannelsWithJsonSchemas) {
  const Json message = Json::parse(advertise());
  EXPECT_EQ(message["op"], "advertise");
  ASSERT_EQ(message["channels"].size(), 4u);
  const std::vector<std::string> topics = {"/wheeltec/telemetry", "/wheeltec/status", "/wheeltec/odom", "/wheeltec/imu"};
  for (std::size_t i = 0; i < 4; ++i) {
    const Json& channel = message["channels"][i];
    EXPECT_EQ(channel["topic"], topics[i]);
    EXPECT_EQ(channel["encoding"], "json");
    EXPECT_EQ(channel["id"], i + 1);
    EXPECT_TRUE(Json::parse(channel["schema"].get<std::string>()).is_object()) << channel["schema"];
  }
  EXPECT_EQ(message["channels"][2]["schemaName"], "foxglove.PoseInFrame");
}

TEST(Foxglove, ServerInfoOffersClientPublish) {
  const Json info = Json::parse(server_info("7", {{"low_battery_v", "10.8"}}));
  EXPECT_EQ(info["op"], "serverInfo");
  EXPECT_EQ(info["capabilities"], Json::array({"clientPublish"}));
  EXPECT_EQ(info["supportedEncodings"], Json::array({"json"}));
  EXPECT_EQ(info["sessionId"], "7");
  EXPECT_EQ(info["metadata"]["low_battery_v"], "10.8");
}

TEST(Foxglove, MessageDataIsOpcodeSubscriptionTimestampPayload) {
  const std::string frame = message_data(0x01020304, 0x1122334455667788ULL, "{}");
  ASSERT_EQ(frame.size(), 15u);
  EXPECT_EQ(frame[0], '\x01');
  EXPECT_EQ(frame.substr(1, 4), std::string("\x04\x03\x02\x01", 4));
  EXPECT_EQ(frame.substr(5, 8), std::string("\x88\x77\x66\x55\x44\x33\x22\x11", 8));
  EXPECT_EQ(frame.substr(13), "{}");
}

TEST(Foxglove, StatusCarriesLevelMessageAndId) {
  const Json message = Json::parse(status(Level::error, "no", "drive-refused"));
  EXPECT_EQ(message["op"], "status");
  EXPECT_EQ(message["level"], 2);
  EXPECT_EQ(message["message"], "no");
  EXPECT_EQ(message["id"], "drive-refused");
  EXPECT_FALSE(Json::parse(status(Level::info, "x")).contains("id"));
  // Invalid UTF-8 in a message (it may quote a client) does not throw.
  EXPECT_NO_THROW(status(Level::error, "bad \xff byte"));
}

TEST(Foxglove, ParsesSubscribeAndUnsubscribe) {
  const auto message = parse_text(R"({"op":"subscribe","subscriptions":[{"id":5,"channelId":1},{"id":6,"channelId":2}]})");
  const auto* subscribe = std::get_if<Subscribe>(&message);
  ASSERT_NE(subscribe, nullptr);
  ASSERT_EQ(subscribe->subscriptions.size(), 2u);
  EXPECT_EQ(subscribe->subscriptions[1].subscription_id, 6u);
  EXPECT_EQ(subscribe->subscriptions[1].channel_id, 2u);
  const auto other = parse_text(R"({"op":"unsubscribe","subscriptionIds":[5]})");
  ASSERT_TRUE(std::holds_alternative<Unsubscribe>(other));
  EXPECT_EQ(std::get<Unsubscribe>(other).subscription_ids, std::vector<std::uint32_t>{5});
}

TEST(Foxglove, ParsesClientAdvertise) {
  const auto message =
      parse_text(R"({"op":"advertise","channels":[{"id":2,"topic":"/wheeltec/cmd_vel","encoding":"json","schemaName":"x"}]})");
  const auto* advertise = std::get_if<ClientAdvertise>(&message);
  ASSERT_NE(advertise, nullptr);
  ASSERT_EQ(advertise->channels.size(), 1u);
  EXPECT_EQ(advertise->channels[0].id, 2u);
  EXPECT_EQ(advertise->channels[0].topic, "/wheeltec/cmd_vel");
}

TEST(Foxglove, MalformedTextIsAProtocolErrorNeverAnException) {
  for (const char* text : {"", "not json", "[]", "{}", R"({"op":5})", R"({"op":"subscribe"})",
                           R"({"op":"subscribe","subscriptions":[{"id":-1,"channelId":1}]})",
                           R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":99999999999}]})",
                           R"({"op":"subscribe","subscriptions":[5]})", R"({"op":"unsubscribe","subscriptionIds":["a"]})",
                           R"({"op":"advertise","channels":[{"id":1}]})", R"({"op":"fly"})"}) {
    ClientMessage message;
    ASSERT_NO_THROW(message = parse_text(text)) << text;
    EXPECT_TRUE(std::holds_alternative<ProtocolError>(message)) << text;
  }
}

TEST(Foxglove, DeepNestingAndKeysGivenTwiceAreRefused) {
  const std::string deep = R"({"op":"subscribe","subscriptions":)" + std::string(30000, '[') + std::string(30000, ']') + "}";
  const auto nested = parse_text(deep);
  ASSERT_TRUE(std::holds_alternative<ProtocolError>(nested));
  EXPECT_EQ(std::get<ProtocolError>(nested).message, "nested deeper than 8 levels");
  const auto twice = parse_cmd_vel(R"({"vx":0.3,"vx":-0.3})");
  ASSERT_TRUE(std::holds_alternative<ProtocolError>(twice));
  EXPECT_EQ(std::get<ProtocolError>(twice).message, "cmd_vel: duplicate key \"vx\"");
  EXPECT_TRUE(std::holds_alternative<ProtocolError>(parse_cmd_vel(std::string(60000, '{'))));
}

TEST(Foxglove, ParsesClientPublishAndRefusesShortOrUnknownFrames) {
  const std::string frame("\x01\x02\x00\x00\x00{\"vx\":1}", 13);  // the payload is a view into it
  const auto publish = parse_binary(frame);
  ASSERT_TRUE(std::holds_alternative<ClientPublish>(publish));
  EXPECT_EQ(std::get<ClientPublish>(publish).channel_id, 2u);
  EXPECT_EQ(std::get<ClientPublish>(publish).payload, "{\"vx\":1}");
  EXPECT_TRUE(std::holds_alternative<ProtocolError>(parse_binary("")));
  EXPECT_TRUE(std::holds_alternative<ProtocolError>(parse_binary(std::string("\x01\x02", 2))));
  EXPECT_TRUE(std::holds_alternative<ProtocolError>(parse_binary(std::string("\x07\x00\x00\x00\x00", 5))));
}

TEST(Foxglove, CmdVelTakesVxVyWzAndNothingElse) {
  const auto velocity = parse_cmd_vel(R"({"vx":0.3,"wz":-1})");
  ASSERT_TRUE(std::holds_alternative<client::Velocity>(velocity));
  EXPECT_DOUBLE_EQ(std::get<client::Velocity>(velocity).vx, 0.3);
  EXPECT_DOUBLE_EQ(std::get<client::Velocity>(velocity).vy, 0.0);
  EXPECT_DOUBLE_EQ(std::get<client::Velocity>(velocity).wz, -1.0);
  for (const char* bad : {"", "x", "[1]", R"({"vx":"1"})", R"({"speed":1})", R"({"vx":null})", R"({"vx":1e999})"}) {
    EXPECT_TRUE(std::holds_alternative<ProtocolError>(parse_cmd_vel(bad))) << bad;
  }
}

TEST(Foxglove, OdomIsAPoseInFrameWithTheYawAsQuaternion) {
  client::Telemetry record;
  record.time = 1763800000.5;
  record.odom = {1.5, -2.0, 3.14159265358979 / 2};
  const Json pose = odom_pose(record);
  EXPECT_EQ(pose["frame_id"], "odom");
  EXPECT_EQ(pose["timestamp"]["sec"], 1763800000u);
  EXPECT_EQ(pose["timestamp"]["nsec"], 500000000u);
  EXPECT_DOUBLE_EQ(pose["pose"]["position"]["x"].get<double>(), 1.5);
  EXPECT_NEAR(pose["pose"]["orientation"]["z"].get<double>(), std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(pose["pose"]["orientation"]["w"].get<double>(), std::sqrt(0.5), 1e-9);
}

TEST(Foxglove, ImuCarriesGyroAccelAndOrientation) {
  client::Telemetry record;
  record.gyro = {0.1, 0.2, 0.3};
  record.accel = {1, 2, 9.8};
  record.orientation = client::Orientation{0.5, 0.5, 0.5, 0.5, 0, 0, 0};
  const Json message = imu(record);
  EXPECT_DOUBLE_EQ(message["angular_velocity"]["z"].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(message["linear_acceleration"]["z"].get<double>(), 9.8);
  EXPECT_DOUBLE_EQ(message["orientation"]["w"].get<double>(), 0.5);
  EXPECT_EQ(timestamp_ns(-1), 0u);
  EXPECT_EQ(timestamp_ns(2.0), 2000000000u);
}

}  // namespace
}  // namespace wheeltec::web::foxglove
