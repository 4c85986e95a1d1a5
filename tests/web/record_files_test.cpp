// Which of the recorder's files wheeltec-web offers, in which order, as which JSON, and the
// name a download path asks for (web/record_files.hpp).

#include "record_files.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace wheeltec::web {
namespace {

DirectoryEntry file(std::string name, std::uint64_t bytes = 100) { return {std::move(name), true, bytes}; }

TEST(RecordFiles, ARecordingsNameGivesItsTriggerAndTime) {
  const auto deadman = record_of_name("20261127T153012Z-deadman.mcap");
  ASSERT_TRUE(deadman);
  EXPECT_EQ(deadman->name, "20261127T153012Z-deadman.mcap");
  EXPECT_EQ(deadman->trigger, "deadman");
  EXPECT_EQ(deadman->time, 1795793412);  // date -u -d 2026-11-27T15:30:12Z +%s
  EXPECT_EQ(record_of_name("20261127T153012Z-continuous.mcap")->trigger, "continuous");
  EXPECT_EQ(record_of_name("19700101T000000Z-link-down.mcap")->time, 0);
  EXPECT_EQ(record_of_name("20261127T153012Z-commands-ignored.mcap")->trigger, "commands-ignored");
}

TEST(RecordFiles, OnlyWholeFilesTheRecorderNamesAreRecordings) {
  for (const char* name : {"20261127T153012Z-deadman.mcap.part",  // being written
                           "20261127T153012Z-deadman.MCAP", "20261127T153012Z-unknown.mcap", "notes.txt", "",
                           ".", "..", "../20261127T153012Z-deadman.mcap", "/20261127T153012Z-deadman.mcap",
                           "x/20261127T153012Z-deadman.mcap", "20261127T153012Z-deadman.mcap/",
                           "..%2F20261127T153012Z-deadman.mcap", "20261127T153012Z-deadman.mcap%00",
                           "20261131T153012Z-deadman.mcap",  // no 31 November
                           "20261127T153012Z-deadman.mcap?x=1", " 20261127T153012Z-deadman.mcap"}) {
    EXPECT_FALSE(record_of_name(name)) << name;
  }
  EXPECT_FALSE(record_of_name(std::string_view("20261127T153012Z-deadman.mcap\0", 30)));
}

TEST(RecordFiles, TheListIsNewestFirstWithoutPartsForeignFilesOrSymlinks) {
  const std::vector<DirectoryEntry> entries{
      file("20261126T080000Z-battery-low.mcap", 10),
      file("20261127T170000Z-mark.mcap.part", 5),  // newest, but still being written
      file("20261127T153012Z-deadman.mcap", 3000),
      {"20261127T190000Z-halted.mcap", false, 0},  // a symlink or a directory: lstat says not regular
      file("notes.txt", 1),
      file("20261127T160000Z-continuous.mcap", 7),
      file("20261127T153012Z-continuous.mcap", 8),  // the same second as the deadman file
  };
  const auto list = recordings(entries);
  std::vector<std::string> names;
  for (const auto& each : list) names.push_back(each.name);
  EXPECT_EQ(names, (std::vector<std::string>{"20261127T160000Z-continuous.mcap", "20261127T153012Z-deadman.mcap",
                                             "20261127T153012Z-continuous.mcap",
                                             "20261126T080000Z-battery-low.mcap"}));
  EXPECT_EQ(list[1].bytes, 3000u);
  EXPECT_EQ(list[3].trigger, "battery-low");
  EXPECT_TRUE(recordings({}).empty());
}

TEST(RecordFiles, TheJsonNamesEachFieldAndAnEmptyListIsAList) {
  EXPECT_EQ(nlohmann::json::parse(recordings_json({})), nlohmann::json::parse(R"({"records": []})"));
  const auto list = recordings({file("20261127T153012Z-deadman.mcap", 5000000000)});
  EXPECT_EQ(nlohmann::json::parse(recordings_json(list)), nlohmann::json::parse(R"({"records": [
      {"name": "20261127T153012Z-deadman.mcap", "trigger": "deadman", "time": 1795793412, "bytes": 5000000000}]})"));
}

TEST(RecordFiles, TheNameOfADownloadPath) {
  EXPECT_EQ(record_name_in_path("/api/records/20261127T153012Z-deadman.mcap"), "20261127T153012Z-deadman.mcap");
  EXPECT_EQ(record_name_in_path("/api/records/"), "");
  EXPECT_EQ(record_messages_name_in_path("/api/records/20261127T153012Z-deadman.mcap/messages"),
            "20261127T153012Z-deadman.mcap");
  EXPECT_EQ(record_messages_name_in_path("/api/records/20261127T153012Z-deadman.mcap"), std::nullopt);
  EXPECT_EQ(record_messages_name_in_path("/api/records//messages"), std::nullopt);
  EXPECT_EQ(record_messages_name_in_path("/api/records/messages"), std::nullopt);
  EXPECT_EQ(record_name_in_path("/api/records/../etc/passwd"), "../etc/passwd");  // then not a recording
  EXPECT_FALSE(record_name_in_path("/api/records"));  // the list
  EXPECT_FALSE(record_name_in_path("/api/recordsX/20261127T153012Z-deadman.mcap"));
  EXPECT_FALSE(record_name_in_path("/api/status"));
  EXPECT_FALSE(record_name_in_path("/records/20261127T153012Z-deadman.mcap"));
}

}  // namespace
}  // namespace wheeltec::web
