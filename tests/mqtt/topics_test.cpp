#include "topics.hpp"

#include <gtest/gtest.h>

namespace wheeltec::mqtt {
namespace {

TEST(MqttTopics, AreUnderPrefixAndRobot) {
  const Topics topics("wheeltec", "r1");
  EXPECT_EQ(topics.telemetry(), "wheeltec/r1/telemetry");
  EXPECT_EQ(topics.status(), "wheeltec/r1/status");
  EXPECT_EQ(topics.online(), "wheeltec/r1/online");
  EXPECT_EQ(topics.stats(), "wheeltec/r1/stats");
  EXPECT_EQ(topics.result(), "wheeltec/r1/cmd/result");
  EXPECT_EQ(topics.command_topics(),
            (std::vector<std::string>{"wheeltec/r1/cmd/drive", "wheeltec/r1/cmd/stop", "wheeltec/r1/cmd/enable",
                                      "wheeltec/r1/cmd/disable", "wheeltec/r1/cmd/reset_odometry",
                                      "wheeltec/r1/cmd/estop", "wheeltec/r1/cmd/release", "wheeltec/all/cmd/estop"}));
  EXPECT_EQ(topics.fleet_estop(), "wheeltec/all/cmd/estop");
  EXPECT_EQ(topics.command(Command::reset_odometry), "wheeltec/r1/cmd/reset_odometry");
}

TEST(MqttTopics, MultiLevelPrefix) {
  const Topics topics("site/hall-2", "r1");
  EXPECT_EQ(topics.telemetry(), "site/hall-2/r1/telemetry");
  EXPECT_EQ(topics.fleet_estop(), "site/hall-2/all/cmd/estop");
  EXPECT_EQ(prefix_problem("site/hall-2"), std::nullopt);
}

TEST(MqttTopics, CommandOfTopic) {
  const Topics topics("wheeltec", "r1");
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/drive"), Command::drive);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/stop"), Command::stop);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/enable"), Command::enable);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/disable"), Command::disable);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/reset_odometry"), Command::reset_odometry);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/estop"), Command::estop);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/release"), Command::release);
  EXPECT_EQ(topics.command_of("wheeltec/all/cmd/estop"), Command::estop);  // the fleet's
  EXPECT_EQ(topics.command_of("wheeltec/all/cmd/release"), std::nullopt);  // one by one only
  EXPECT_EQ(topics.command_of("wheeltec/all/cmd/drive"), std::nullopt);
  EXPECT_EQ(topics.command_of("other/all/cmd/estop"), std::nullopt);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/result"), std::nullopt);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/drive/x"), std::nullopt);
  EXPECT_EQ(topics.command_of("wheeltec/r2/cmd/drive"), std::nullopt);
  EXPECT_EQ(topics.command_of("wheeltec/r1/cmd/"), std::nullopt);
  EXPECT_EQ(topics.command_of("wheeltec/r10/cmd/drive"), std::nullopt);
}

TEST(MqttTopics, OwnsItsTopicsButNotTheResultTopic) {
  const Topics topics("wheeltec", "r1");
  EXPECT_TRUE(topics.owns("wheeltec/r1/status"));
  EXPECT_TRUE(topics.owns("wheeltec/r1/cmd/drive"));
  EXPECT_FALSE(topics.owns("wheeltec/r1/cmd/result"));
  EXPECT_FALSE(topics.owns("wheeltec/r10/status"));
  EXPECT_FALSE(topics.owns("replies/op1"));
}

TEST(MqttTopics, RefusesWildcardsEmptyLevelsAndBrokerTopics) {
  for (const char* bad : {"", "a/+", "a/#", "+", "#", "a//b", "/a", "a/", "$SYS", "a\nb", "a/b+c"}) {
    EXPECT_NE(prefix_problem(bad), std::nullopt) << bad;
  }
  for (const char* bad : {"", "r/1", "+", "#", "r#1", "$r", "\x7f", "\xff"}) {
    EXPECT_NE(robot_name_problem(bad), std::nullopt) << bad;
  }
  EXPECT_NE(robot_name_problem(std::string(2000, 'r')), std::nullopt);
  EXPECT_EQ(robot_name_problem("robot-7.lab"), std::nullopt);
  EXPECT_EQ(robot_name_problem("r\xc3\xb6" "bot"), std::nullopt);  // UTF-8
  EXPECT_NE(robot_name_problem("r\xc3"), std::nullopt);            // cut UTF-8
}

TEST(MqttTopics, ProblemsSayWhat) {
  EXPECT_EQ(*prefix_problem("a/+"), "holds the MQTT wildcard '+'");
  EXPECT_EQ(*prefix_problem("a//b"), "has an empty topic level");
  EXPECT_EQ(*robot_name_problem("a/b"), "holds '/' (a robot name is one topic level)");
  EXPECT_EQ(*robot_name_problem("all"), "\"all\" is reserved: PREFIX/all/cmd/estop is the whole fleet's emergency stop");
  EXPECT_EQ(robot_name_problem("All"), std::nullopt);  // topics are case-sensitive
  EXPECT_EQ(robot_name_problem("all2"), std::nullopt);
}

}  // namespace
}  // namespace wheeltec::mqtt
