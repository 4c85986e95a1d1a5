#include "retention.hpp"

#include <gtest/gtest.h>

namespace wheeltec::record {
namespace {

using Names = std::vector<std::string>;

const std::vector<StoredFile> kFiles{
    {"20261127T153012Z-deadman.mcap", 400},
    {"20261125T080000Z-mark.mcap", 300},        // the oldest
    {"20261126T120000Z-continuous.mcap", 200},
    {"20261127T160000Z-offline.mcap", 100},     // the newest
};

Names removed(const std::vector<StoredFile>& files, std::uint64_t max_bytes, Names being_written = {},
              std::optional<std::string> last_finished = std::nullopt) {
  return plan_retention({files, max_bytes, std::move(being_written), std::move(last_finished)}).remove;
}

TEST(RecordRetention, NothingWhileTheFilesFit) {
  EXPECT_EQ(removed(kFiles, 1000), Names{});
  EXPECT_EQ(removed({}, 0), Names{});
  const RetentionPlan plan = plan_retention({kFiles, 1000, {}, {}});
  EXPECT_EQ(plan.bytes_kept, 1000u);
  EXPECT_FALSE(plan.kept_over_limit);
}

TEST(RecordRetention, OldestFirstUntilTheRestFits) {
  EXPECT_EQ(removed(kFiles, 999), Names{"20261125T080000Z-mark.mcap"});
  EXPECT_EQ(removed(kFiles, 500), (Names{"20261125T080000Z-mark.mcap", "20261126T120000Z-continuous.mcap"}));
  const RetentionPlan plan = plan_retention({kFiles, 500, {}, {}});
  EXPECT_EQ(plan.bytes_kept, 500u);
  EXPECT_FALSE(plan.kept_over_limit);
}

// Issue 41 item 5: a limit below one file's size deleted the file just written.
TEST(RecordRetention, TheNewestFinishedFileIsKeptWhenItAloneIsOverTheLimit) {
  const RetentionPlan plan = plan_retention({kFiles, 0, {}, {}});
  EXPECT_EQ(plan.remove, (Names{"20261125T080000Z-mark.mcap", "20261126T120000Z-continuous.mcap",
                                "20261127T153012Z-deadman.mcap"}));
  EXPECT_EQ(plan.bytes_kept, 100u);
  ASSERT_TRUE(plan.kept_over_limit);
  EXPECT_EQ(*plan.kept_over_limit, (StoredFile{"20261127T160000Z-offline.mcap", 100}));

  const std::vector<StoredFile> one{{"20261201T220000Z-mark.mcap", 50'000}};
  const RetentionPlan alone = plan_retention({one, 15'000, {}, "20261201T220000Z-mark.mcap"});
  EXPECT_EQ(alone.remove, Names{});
  ASSERT_TRUE(alone.kept_over_limit);
  EXPECT_EQ(alone.kept_over_limit->name, "20261201T220000Z-mark.mcap");
}

TEST(RecordRetention, NothingIsReportedOverTheLimitOnceTheRestFits) {
  EXPECT_FALSE(plan_retention({kFiles, 100, {}, {}}).kept_over_limit);
  EXPECT_EQ(removed(kFiles, 100).size(), 3u);
}

TEST(RecordRetention, TheFileFinishedLastIsKeptEvenWhenANewerNamedOneExists) {
  // An incident from 15:30 finished after a continuous file that started at 16:00.
  const std::vector<StoredFile> files{
      {"20261127T150000Z-continuous.mcap", 100},
      {"20261127T153000Z-deadman.mcap", 100},
      {"20261127T160000Z-continuous.mcap", 100},
  };
  const RetentionPlan plan = plan_retention({files, 0, {}, "20261127T153000Z-deadman.mcap"});
  EXPECT_EQ(plan.remove, Names{"20261127T150000Z-continuous.mcap"});
  ASSERT_TRUE(plan.kept_over_limit);
  EXPECT_EQ(plan.kept_over_limit->name, "20261127T153000Z-deadman.mcap");
  // A last finished file that is gone (deleted by hand) leaves the newest by name.
  EXPECT_EQ(removed(files, 0, {}, "20261127T120000Z-mark.mcap"),
            (Names{"20261127T150000Z-continuous.mcap", "20261127T153000Z-deadman.mcap"}));
}

TEST(RecordRetention, NeverDeletesTheFileBeingWritten) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"20261125T070000Z-halted.mcap.part", 5000});  // oldest of all, and open
  const Names doomed = removed(files, 5000, {"20261125T070000Z-halted.mcap.part"});
  EXPECT_EQ(doomed.size(), 3u);  // all but the newest whole one
  for (const std::string& name : doomed) {
    EXPECT_NE(name, "20261125T070000Z-halted.mcap.part");
    EXPECT_NE(name, "20261127T160000Z-offline.mcap");
  }
  // Its size counts: the others go, although they alone would fit.
  EXPECT_EQ(removed(files, 5500, {"20261125T070000Z-halted.mcap.part"}),
            (Names{"20261125T080000Z-mark.mcap", "20261126T120000Z-continuous.mcap"}));
}

TEST(RecordRetention, NeverDeletesEitherOfTwoFilesBeingWritten) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"20261125T000000Z-continuous.mcap.part", 50});
  files.push_back({"20261125T000001Z-mark.mcap.part", 50});
  const Names doomed = removed(files, 0, {"20261125T000000Z-continuous.mcap.part", "20261125T000001Z-mark.mcap.part"});
  EXPECT_EQ(doomed.size(), 3u);
}

TEST(RecordRetention, PartFilesLeftByACrashAreDeletedInTheirTurn) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"20261126T000000Z-reboot.mcap.part", 250});  // not being written
  EXPECT_EQ(removed(files, 900), (Names{"20261125T080000Z-mark.mcap", "20261126T000000Z-reboot.mcap.part"}));
  EXPECT_EQ(removed(files, 1250), Names{});
  // Never the newest finished file, even when a crashed part is named later.
  files.push_back({"20261128T000000Z-mark.mcap.part", 10});
  const Names all_but_newest = removed(files, 0);
  EXPECT_EQ(all_but_newest.size(), 5u);
  EXPECT_EQ(all_but_newest.back(), "20261128T000000Z-mark.mcap.part");
}

TEST(RecordRetention, OtherFilesAreNeitherCountedNorDeleted) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"README.txt", 1'000'000});
  files.push_back({"00000000T000000Z-x.mcap", 1'000'000});
  EXPECT_EQ(removed(files, 1000), Names{});
  EXPECT_EQ(removed(files, 999), Names{"20261125T080000Z-mark.mcap"});
}

TEST(RecordRetention, FilesOfTheSameSecondGoInNameOrder) {
  const std::vector<StoredFile> files{{"20261127T153012Z-offline.mcap", 10},
                                      {"20261127T153012Z-halted.mcap", 10},
                                      {"20261127T153012Z-mark.mcap", 10}};
  EXPECT_EQ(removed(files, 20), Names{"20261127T153012Z-halted.mcap"});
  EXPECT_EQ(removed(files, 0), (Names{"20261127T153012Z-halted.mcap", "20261127T153012Z-mark.mcap"}));
}

}  // namespace
}  // namespace wheeltec::record
