// wheeltec/drive_velocity.hpp: the one check of a drive's velocity that the daemon and the
// bridges share, on both JSON flavours and both velocity types.

#include "wheeltec/drive_velocity.hpp"

#include <gtest/gtest.h>

#include <limits>

#include <nlohmann/json.hpp>

#include "wheeltec/client/records.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {
namespace {

TEST(DriveVelocity, ReadsTheThreeMembersAndLeavesAbsentOnesZero) {
  Velocity velocity;
  EXPECT_FALSE(read_drive_velocity(nlohmann::json{{"vx", 0.3}, {"wz", -1}}, velocity));
  EXPECT_EQ(velocity, (Velocity{0.3, 0.0, -1.0}));
  client::Velocity theirs;
  EXPECT_FALSE(read_drive_velocity(nlohmann::ordered_json{{"vy", 0.1}}, theirs));
  EXPECT_DOUBLE_EQ(theirs.vy, 0.1);
  EXPECT_DOUBLE_EQ(theirs.vx, 0.0);
}

TEST(DriveVelocity, NamesTheFirstProblem) {
  const auto problem = [](const nlohmann::json& object) {
    Velocity velocity;
    return read_drive_velocity(object, velocity).value_or("none");
  };
  EXPECT_EQ(problem({{"speed", 1}}), "unknown param \"speed\"");
  EXPECT_EQ(problem({{"VX", 1}}), "unknown param \"VX\"");  // names are exact
  EXPECT_EQ(problem({{"vx", "fast"}}), "vx must be a number, got string");
  EXPECT_EQ(problem({{"wz", nullptr}}), "wz must be a number, got null");
  EXPECT_EQ(problem({{"vy", std::numeric_limits<double>::infinity()}}), "vy must be finite");
  EXPECT_EQ(problem({{"vx", std::numeric_limits<double>::quiet_NaN()}}), "vx must be finite");
  EXPECT_EQ(problem(nlohmann::json::array({1, 2})), "a drive must be an object {\"vx\", \"vy\", \"wz\"}");
  EXPECT_EQ(problem(nlohmann::json::object()), "none");
}

TEST(DriveVelocity, AMemberAtATimeLeavesTheOthersAlone) {
  Velocity velocity{0.1, 0.2, 0.3};
  EXPECT_FALSE(read_drive_member("wz", nlohmann::json(0.5), velocity));
  EXPECT_EQ(velocity, (Velocity{0.1, 0.2, 0.5}));
  EXPECT_TRUE(read_drive_member("vx", nlohmann::json(true), velocity));
  EXPECT_EQ(velocity.vx, 0.1);  // unchanged by a refused member
  EXPECT_EQ(*read_drive_member("operator", nlohmann::json("x"), velocity), "unknown param \"operator\"");
}

}  // namespace
}  // namespace wheeltec
