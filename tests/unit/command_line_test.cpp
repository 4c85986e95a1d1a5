#include "wheeltec/command_line.hpp"

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace wheeltec::command_line {
namespace {

// Parses `arguments` (the program name first); the exit code, and stderr in `errors`.
std::optional<int> parse_arguments(CLI::App& app, std::vector<std::string> arguments, std::string& errors) {
  std::vector<char*> argv;
  for (auto& argument : arguments) argv.push_back(argument.data());
  testing::internal::CaptureStderr();
  const auto exit_code = parse(app, static_cast<int>(argv.size()), argv.data());
  errors = testing::internal::GetCapturedStderr();
  return exit_code;
}

TEST(CommandLineParse, ALogLevelIsOneOfTheLevels) {
  CLI::App app("test", "prog");
  std::optional<std::string> level;
  add_log_level_option(app, level);
  std::string errors;
  EXPECT_EQ(parse_arguments(app, {"prog"}, errors), std::nullopt);
  EXPECT_FALSE(level.has_value()) << "not given: the config file's log.level stays";
  EXPECT_EQ(parse_arguments(app, {"prog", "--log-level", "debug"}, errors), std::nullopt);
  EXPECT_EQ(level, "debug");
}

TEST(CommandLineParse, AnUnknownLogLevelIsAOneLineUsageError) {
  CLI::App app("test", "prog");
  std::string level = "info";
  add_log_level_option(app, level);
  std::string errors;
  EXPECT_EQ(parse_arguments(app, {"prog", "--log-level", "loud"}, errors), 2);
  EXPECT_EQ(errors, "prog: --log-level: loud not in {trace,debug,info,warn,error} (see --help)\n");
  EXPECT_EQ(level, "info");
  EXPECT_NE(app.help().find("trace|debug|info|warn|error"), std::string::npos) << app.help();
}

TEST(CommandLineParse, FiniteInRefusesNotANumberAndOutOfRange) {
  CLI::App app("test", "prog");
  double rate = 0.0;
  app.add_option("--rate", rate)->check(finite_in(0.0, 100.0, LowBound::exclusive));
  std::string errors;
  EXPECT_EQ(parse_arguments(app, {"prog", "--rate", "50"}, errors), std::nullopt);
  EXPECT_EQ(rate, 50.0);
  EXPECT_EQ(parse_arguments(app, {"prog", "--rate", "nan"}, errors), 2);
  EXPECT_NE(errors.find("expected a number, got nan"), std::string::npos) << errors;
  EXPECT_EQ(parse_arguments(app, {"prog", "--rate", "0"}, errors), 2);
  EXPECT_NE(errors.find("not in (0, 100]"), std::string::npos) << errors;
}

}  // namespace
}  // namespace wheeltec::command_line
