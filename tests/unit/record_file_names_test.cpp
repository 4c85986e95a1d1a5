#include "wheeltec/record/file_names.hpp"

#include <cstdlib>

#include <gtest/gtest.h>

namespace wheeltec::record {
namespace {

using std::chrono::milliseconds;
using std::chrono::seconds;

const RealtimeNanos kSpecExample{seconds(1'795'793'412)};  // 2026-11-27T15:30:12Z

TEST(RecordFileNames, IncidentFilesAreNamedByTheUtcSecondOfTheFirstTrigger) {
  EXPECT_EQ(file_name(kSpecExample, Trigger::deadman), "20261127T153012Z-deadman.mcap");
  EXPECT_EQ(file_name(kSpecExample + milliseconds(999), Trigger::link_down), "20261127T153012Z-link-down.mcap");
  EXPECT_EQ(file_name(RealtimeNanos{}, Trigger::daemon_lost), "19700101T000000Z-daemon-lost.mcap");
}

TEST(RecordFileNames, ContinuousFilesAreNamedByTheirStart) {
  EXPECT_EQ(file_name(kSpecExample, Continuous{}), "20261127T153012Z-continuous.mcap");
}

TEST(RecordFileNames, AreUtcWhateverTheLocalZone) {
  const char* saved = std::getenv("TZ");
  const std::string previous = saved ? saved : "";
  ::setenv("TZ", "Asia/Kolkata", 1);
  ::tzset();
  const std::string name = file_name(kSpecExample, Trigger::mark);
  if (saved) {
    ::setenv("TZ", previous.c_str(), 1);
  } else {
    ::unsetenv("TZ");
  }
  ::tzset();
  EXPECT_EQ(name, "20261127T153012Z-mark.mcap");
}

TEST(RecordFileNames, AreWrittenUnderAPartName) {
  EXPECT_EQ(part_name("20261127T153012Z-mark.mcap"), "20261127T153012Z-mark.mcap.part");
}

TEST(RecordFileNames, ReadBackWhatTheyWereMadeOf) {
  for (const Trigger trigger : kTriggers) {
    const std::string name = file_name(kSpecExample, trigger);
    EXPECT_EQ(parse_file_name(name), (ParsedFileName{kSpecExample, trigger, FileCompleteness::whole})) << name;
    EXPECT_EQ(parse_file_name(part_name(name)), (ParsedFileName{kSpecExample, trigger, FileCompleteness::part}))
        << name;
  }
  EXPECT_EQ(parse_file_name("20261127T153012Z-continuous.mcap"),
            (ParsedFileName{kSpecExample, Continuous{}, FileCompleteness::whole}));
  EXPECT_EQ(parse_file_name("20240229T000000Z-offline.mcap")->time, RealtimeNanos{seconds(1'709'164'800)});
}

TEST(RecordFileNames, OtherNamesAreNotOurs) {
  for (const char* name : {"", "notes.txt", ".mcap", "20261127T153012Z.mcap", "20261127T153012Z-.mcap",
                           "20261127T153012Z-deadmen.mcap", "20261127T153012Z-deadman.mcap.tmp",
                           "20261127T153012Z-deadman.part", "20261127T153012Z-deadman", "20261127T153012-deadman.mcap",
                           "20261127 153012Z-deadman.mcap", "2026112T153012Z-deadman.mcap", "20261327T153012Z-deadman.mcap",
                           "20260230T153012Z-deadman.mcap", "20261127T243012Z-deadman.mcap", "20261127T156012Z-deadman.mcap",
                           "20261127T153060Z-deadman.mcap", "2026+127T153012Z-deadman.mcap", "19691231T235959Z-mark.mcap",
                           "x20261127T153012Z-deadman.mcap", "20261127T153012Z-deadman.mcap.part.part"}) {
    EXPECT_EQ(parse_file_name(name), std::nullopt) << name;
  }
}

}  // namespace
}  // namespace wheeltec::record
