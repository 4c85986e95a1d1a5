#include <gtest/gtest.h>

#include <cstdlib>
#include <optional>
#include <string>

#include "arguments.hpp"

namespace wheeltecctl {
namespace {

// Sets $WHEELTEC_SOCKET (nullptr: unsets it) and restores it at the end of the test.
class SocketEnvironment {
 public:
  explicit SocketEnvironment(const char* value) {
    if (const char* old = std::getenv("WHEELTEC_SOCKET")) saved_ = old;
    if (value != nullptr) {
      ::setenv("WHEELTEC_SOCKET", value, 1);
    } else {
      ::unsetenv("WHEELTEC_SOCKET");
    }
  }
  ~SocketEnvironment() {
    if (saved_) {
      ::setenv("WHEELTEC_SOCKET", saved_->c_str(), 1);
    } else {
      ::unsetenv("WHEELTEC_SOCKET");
    }
  }

 private:
  std::optional<std::string> saved_;
};

TEST(CliArguments, SocketOptionWinsOverEnvironment) {
  const SocketEnvironment environment("/tmp/env.sock");
  EXPECT_EQ(resolve_socket_path(std::string("/tmp/option.sock")), "/tmp/option.sock");
}

TEST(CliArguments, EnvironmentWinsOverDefault) {
  const SocketEnvironment environment("/tmp/env.sock");
  EXPECT_EQ(resolve_socket_path(std::nullopt), "/tmp/env.sock");
}

TEST(CliArguments, DefaultWhenNeitherIsSet) {
  {
    const SocketEnvironment environment(nullptr);
    EXPECT_EQ(resolve_socket_path(std::nullopt), "/run/wheeltecd/wheeltecd.sock");
  }
  const SocketEnvironment environment("");
  EXPECT_EQ(resolve_socket_path(std::nullopt), "/run/wheeltecd/wheeltecd.sock");
}

TEST(CliArguments, FiniteNumbers) {
  EXPECT_EQ(parse_finite_number("0.3"), 0.3);
  EXPECT_EQ(parse_finite_number("-1.5"), -1.5);
  EXPECT_EQ(parse_finite_number("+2"), 2.0);
  EXPECT_EQ(parse_finite_number("1e-1"), 0.1);
  EXPECT_EQ(parse_finite_number(".5"), 0.5);
}

TEST(CliArguments, RejectsNonNumbers) {
  for (const char* text : {"", "+", "abc", "0.3x", " 1", "1 ", "nan", "inf", "-inf", "1e999", "0x10",
                           "--1"}) {
    EXPECT_FALSE(parse_finite_number(text).has_value()) << text;
  }
}

TEST(CliArguments, TwoPositionalsAreVxAndWz) {
  const auto velocity = parse_drive_velocity({"0.3", "-0.5"});
  ASSERT_TRUE(std::holds_alternative<wheeltec::Velocity>(velocity));
  EXPECT_EQ(std::get<wheeltec::Velocity>(velocity), (wheeltec::Velocity{0.3, 0.0, -0.5}));
}

TEST(CliArguments, ThreePositionalsAreVxVyWz) {
  const auto velocity = parse_drive_velocity({"0.3", "0.1", "0.5"});
  ASSERT_TRUE(std::holds_alternative<wheeltec::Velocity>(velocity));
  EXPECT_EQ(std::get<wheeltec::Velocity>(velocity), (wheeltec::Velocity{0.3, 0.1, 0.5}));
}

TEST(CliArguments, DriveErrorsNameTheProblem) {
  const auto not_number = parse_drive_velocity({"0.3", "fast"});
  ASSERT_TRUE(std::holds_alternative<std::string>(not_number));
  EXPECT_EQ(std::get<std::string>(not_number), "drive: 'fast' is not a number");
  EXPECT_TRUE(std::holds_alternative<std::string>(parse_drive_velocity({"0.3"})));
  EXPECT_TRUE(std::holds_alternative<std::string>(parse_drive_velocity({"1", "2", "3", "4"})));
}

}  // namespace
}  // namespace wheeltecctl
