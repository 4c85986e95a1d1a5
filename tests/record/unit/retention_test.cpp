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

TEST(RecordRetention, NothingWhileTheFilesFit) {
  EXPECT_EQ(files_to_delete(kFiles, 1000, {}), Names{});
  EXPECT_EQ(files_to_delete({}, 0, {}), Names{});
}

TEST(RecordRetention, OldestFirstUntilTheRestFits) {
  EXPECT_EQ(files_to_delete(kFiles, 999, {}), Names{"20261125T080000Z-mark.mcap"});
  EXPECT_EQ(files_to_delete(kFiles, 500, {}), (Names{"20261125T080000Z-mark.mcap", "20261126T120000Z-continuous.mcap"}));
  EXPECT_EQ(files_to_delete(kFiles, 0, {}).size(), 4u);
}

TEST(RecordRetention, NeverDeletesTheFileBeingWritten) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"20261125T070000Z-halted.mcap.part", 5000});  // oldest of all, and open
  const Names doomed = files_to_delete(files, 5000, {"20261125T070000Z-halted.mcap.part"});
  EXPECT_EQ(doomed.size(), 4u);
  for (const std::string& name : doomed) EXPECT_NE(name, "20261125T070000Z-halted.mcap.part");
  // Its size counts: the others go, although they alone would fit.
  EXPECT_EQ(files_to_delete(files, 5500, {"20261125T070000Z-halted.mcap.part"}),
            (Names{"20261125T080000Z-mark.mcap", "20261126T120000Z-continuous.mcap"}));
}

TEST(RecordRetention, NeverDeletesEitherOfTwoFilesBeingWritten) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"20261125T000000Z-continuous.mcap.part", 50});
  files.push_back({"20261125T000001Z-mark.mcap.part", 50});
  const Names doomed =
      files_to_delete(files, 0, {"20261125T000000Z-continuous.mcap.part", "20261125T000001Z-mark.mcap.part"});
  EXPECT_EQ(doomed.size(), 4u);
}

TEST(RecordRetention, PartFilesLeftByACrashAreDeletedInTheirTurn) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"20261126T000000Z-reboot.mcap.part", 250});  // not being written
  EXPECT_EQ(files_to_delete(files, 900, {}),
            (Names{"20261125T080000Z-mark.mcap", "20261126T000000Z-reboot.mcap.part"}));
  EXPECT_EQ(files_to_delete(files, 1250, {}), Names{});
}

TEST(RecordRetention, OtherFilesAreNeitherCountedNorDeleted) {
  std::vector<StoredFile> files = kFiles;
  files.push_back({"README.txt", 1'000'000});
  files.push_back({"00000000T000000Z-x.mcap", 1'000'000});
  EXPECT_EQ(files_to_delete(files, 1000, {}), Names{});
  EXPECT_EQ(files_to_delete(files, 999, {}), Names{"20261125T080000Z-mark.mcap"});
}

TEST(RecordRetention, FilesOfTheSameSecondGoInNameOrder) {
  const std::vector<StoredFile> files{{"20261127T153012Z-offline.mcap", 10}, {"20261127T153012Z-halted.mcap", 10}};
  EXPECT_EQ(files_to_delete(files, 10, {}), Names{"20261127T153012Z-halted.mcap"});
}

}  // namespace
}  // namespace wheeltec::record
