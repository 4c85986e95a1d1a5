// The three programs' command lines, no CAN needed: --help, --version, exit code 2
// on bad usage, and wheeltecd --check-config with defaults, overrides and errors.

#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>
#include <wheeltec/version.hpp>

#include "child_process.hpp"
#include "test_environment.hpp"

namespace integration {
namespace {

using Json = nlohmann::json;

class CommandLine : public ::testing::Test {
 protected:
  CompletedProcess run(const std::string& program, const std::vector<std::string>& arguments) {
    return run_program(program_path(program), arguments, directory_.path());
  }
  std::string write_config(const std::string& name, const std::string& text) {
    const auto path = directory_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  // --check-config output parsed as JSON.
  Json checked_config(const CompletedProcess& completed) {
    try {
      return Json::parse(completed.out);
    } catch (const Json::exception&) {
      ADD_FAILURE() << "--check-config did not print JSON\n" << completed.describe();
      return Json::object();
    }
  }

  TestDirectory directory_;
};

TEST_F(CommandLine, EveryProgramHasHelpAndVersion) {
  for (const std::string program : {"wheeltecd", "wheeltecctl", "wheeltec-emu"}) {
    const auto help = run(program, {"--help"});
    EXPECT_TRUE(help.status.exited_with(0)) << program << " --help\n" << help.describe();
    EXPECT_NE(help.out.find("--"), std::string::npos) << program << " --help lists no options\n" << help.describe();
    const auto version = run(program, {"--version"});
    EXPECT_TRUE(version.status.exited_with(0)) << program << " --version\n" << version.describe();
    EXPECT_NE(version.out.find(wheeltec::kVersion), std::string::npos) << program << "\n" << version.describe();
  }
}

TEST_F(CommandLine, UnknownOptionsExit2WithAnError) {
  for (const std::string program : {"wheeltecd", "wheeltecctl", "wheeltec-emu"}) {
    const auto completed = run(program, {"--no-such-option"});
    EXPECT_TRUE(completed.status.exited_with(2)) << program << "\n" << completed.describe();
    EXPECT_FALSE(completed.err.empty()) << program << "\n" << completed.describe();
  }
  const auto bad_chassis = run("wheeltec-emu", {"--chassis", "hovercraft"});
  EXPECT_TRUE(bad_chassis.status.exited_with(2)) << bad_chassis.describe();
  const auto bad_dialect = run("wheeltecd", {"--dialect", "0x999", "--check-config"});
  EXPECT_TRUE(bad_dialect.status.exited_with(2)) << bad_dialect.describe();
}

TEST_F(CommandLine, CheckConfigPrintsTheDefaults) {
  const auto completed = run("wheeltecd", {"--config", write_config("empty.json", "{}"), "--check-config"});
  ASSERT_TRUE(completed.status.exited_with(0)) << completed.describe();
  const Json config = checked_config(completed);
  // config/wheeltecd.json as shipped holds every default (a unit test checks that).
  std::ifstream shipped(WHEELTEC_SHIPPED_CONFIG);
  ASSERT_TRUE(shipped) << WHEELTEC_SHIPPED_CONFIG;
  const Json defaults = Json::parse(shipped);
  for (const auto& [section, value] : defaults.items()) {
    EXPECT_EQ(config.value(section, Json()), value) << section << "\n" << completed.describe();
  }
}

TEST_F(CommandLine, FlagsOverrideTheConfigFile) {
  const std::string file =
      write_config("wheeltecd.json", R"({"can":{"interface":"can3","dialect":"manual"},"chassis":{"type":"omni"},
                                         "control":{"rate_hz":50},"log":{"level":"warn"}})");
  const auto completed = run("wheeltecd", {"--config", file, "--interface", "vcan5", "--chassis", "diff", "--dialect",
                                           "0x181", "--socket", "/tmp/x.sock", "--log-level", "debug", "--check-config"});
  ASSERT_TRUE(completed.status.exited_with(0)) << completed.describe();
  const Json config = checked_config(completed);
  EXPECT_EQ(config["can"]["interface"], "vcan5");
  EXPECT_EQ(config["can"]["dialect"], "0x181");
  EXPECT_EQ(config["chassis"]["type"], "diff");
  EXPECT_EQ(config["api"]["socket"], "/tmp/x.sock");
  EXPECT_EQ(config["log"]["level"], "debug");
  EXPECT_EQ(config["control"]["rate_hz"], 50) << "keys without a flag come from the file";
}

TEST_F(CommandLine, CheckConfigNamesTheBadKey) {
  const struct {
    const char* text;
    const char* key;
  } cases[] = {
      {R"({"can":{"interfaces":"vcan0"}})", "interfaces"},
      {R"({"control":{"rate_hz":"fast"}})", "rate_hz"},
      {R"({"chassis":{"type":"hovercraft"}})", "type"},
      {R"({"telemetry":{"timeout_s":-1}})", "timeout_s"},
      {R"({"api":{"max_clients":"many"}})", "max_clients"},
      {R"({"colour":"red"})", "colour"},
  };
  int n = 0;
  for (const auto& c : cases) {
    const auto completed =
        run("wheeltecd", {"--config", write_config("bad" + std::to_string(++n) + ".json", c.text), "--check-config"});
    EXPECT_TRUE(completed.status.exited_with(2)) << c.text << "\n" << completed.describe();
    EXPECT_NE(completed.err.find(c.key), std::string::npos) << "the error must name " << c.key << "\n"
                                                            << completed.describe();
  }
  const auto unparsable = run("wheeltecd", {"--config", write_config("broken.json", "{\"can\":"), "--check-config"});
  EXPECT_TRUE(unparsable.status.exited_with(2)) << unparsable.describe();
  const auto missing = run("wheeltecd", {"--config", (directory_ / "absent.json").string(), "--check-config"});
  EXPECT_FALSE(missing.status.exited_with(0)) << missing.describe();
  EXPECT_FALSE(missing.err.empty()) << missing.describe();
}

}  // namespace
}  // namespace integration
