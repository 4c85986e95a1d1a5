#include "triggers.hpp"

#include <gtest/gtest.h>

#include "wheeltec/config/config_document.hpp"

namespace wheeltec::record {
namespace {

// The message of apply_trigger_options' ConfigError, or "" when it accepts the options.
std::string refusal_of(const std::vector<std::string>& enable, const std::vector<std::string>& disable) {
  try {
    apply_trigger_options(default_triggers(), enable, disable);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "";
}

TEST(RecordTriggers, NamesAreTheSpecsAndReadBack) {
  const std::vector<std::string_view> expected{"deadman",     "halted",           "reboot",  "link-down",   "offline",
                                               "battery-low", "commands-ignored", "refused", "daemon-lost", "mark",
                                               "estop"};
  ASSERT_EQ(kTriggers.size(), expected.size());
  for (std::size_t i = 0; i < kTriggers.size(); ++i) {
    EXPECT_EQ(trigger_name(kTriggers[i]), expected[i]);
    EXPECT_EQ(trigger_of_name(expected[i]), kTriggers[i]);
  }
  EXPECT_EQ(trigger_of_name("link_down"), std::nullopt);
  EXPECT_EQ(trigger_of_name("Deadman"), std::nullopt);
  EXPECT_EQ(trigger_of_name(""), std::nullopt);
}

TEST(RecordTriggers, AllButRefusedAreOnByDefault) {
  const TriggerSet defaults = default_triggers();
  for (const Trigger trigger : kTriggers) {
    EXPECT_EQ(defaults.contains(trigger), trigger != Trigger::refused) << trigger_name(trigger);
  }
  EXPECT_EQ(defaults.members().size(), 10u);
  EXPECT_TRUE(defaults.contains(Trigger::estop));
}

TEST(RecordTriggers, TriggerAndNoTriggerChangeTheSet) {
  const TriggerSet set = apply_trigger_options(default_triggers(), {"refused"}, {"mark", "battery-low"});
  EXPECT_TRUE(set.contains(Trigger::refused));
  EXPECT_FALSE(set.contains(Trigger::mark));
  EXPECT_FALSE(set.contains(Trigger::battery_low));
  EXPECT_TRUE(set.contains(Trigger::deadman));
  EXPECT_EQ(apply_trigger_options(default_triggers(), {}, {}), default_triggers());
  EXPECT_EQ(apply_trigger_options(TriggerSet{}, {"mark", "mark"}, {}), TriggerSet{Trigger::mark});
}

TEST(RecordTriggers, UnknownNameIsRefusedNamingIt) {
  const std::string refusal = refusal_of({"deadmen"}, {});
  EXPECT_NE(refusal.find("--trigger"), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("\"deadmen\""), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("daemon-lost"), std::string::npos) << refusal;  // lists the known ones
  const std::string refusal_no = refusal_of({}, {"battery_low"});
  EXPECT_NE(refusal_no.find("--no-trigger"), std::string::npos) << refusal_no;
  EXPECT_NE(refusal_no.find("\"battery_low\""), std::string::npos) << refusal_no;
}

TEST(RecordTriggers, NameGivenToBothOptionsIsRefused) {
  const std::string refusal = refusal_of({"refused", "mark"}, {"mark"});
  EXPECT_NE(refusal.find("\"mark\""), std::string::npos) << refusal;
  EXPECT_NE(refusal.find("--trigger"), std::string::npos) << refusal;
}

}  // namespace
}  // namespace wheeltec::record
