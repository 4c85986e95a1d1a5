// The MCAP reader on files the project did not write: npm's @mcap/core (Foxglove's reference
// writer) wrote them with write_mcap.cjs into $MCAP_NPM_FILES (the mcap.ReaderNpmFiles test
// runs it first): zstd chunks, uncompressed chunks, no chunks, no summary, and lz4 (refused
// by name). Each must read back exactly as KIND.expect.json says, and cut short at any
// length read as far as it is whole.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "wheeltec/mcap/reader.hpp"

namespace {

using wheeltec::mcap::Bytes;
using wheeltec::mcap::ByteView;
using wheeltec::mcap::read_file;
using wheeltec::mcap::ReadError;
using wheeltec::mcap::ReadFile;

std::filesystem::path npm_files() {
  const char* dir = std::getenv("MCAP_NPM_FILES");
  return dir ? dir : "";
}

Bytes file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto* data = reinterpret_cast<const std::byte*>(text.data());
  return Bytes(data, data + text.size());
}

class NpmFile : public ::testing::TestWithParam<std::string> {};

TEST_P(NpmFile, ReadsAsTheWriterMeantIt) {
  ASSERT_FALSE(npm_files().empty()) << "MCAP_NPM_FILES is not set (write_mcap.cjs writes the files)";
  const Bytes file = file_bytes(npm_files() / (GetParam() + ".mcap"));
  ASSERT_FALSE(file.empty()) << GetParam();
  std::ifstream expect_file(npm_files() / (GetParam() + ".expect.json"));
  const nlohmann::json expect = nlohmann::json::parse(expect_file);
  if (expect.contains("error")) {
    try {
      read_file(file);
      FAIL() << GetParam() << " was read";
    } catch (const ReadError& error) {
      EXPECT_NE(std::string(error.what()).find(expect["error"].get<std::string>()), std::string::npos)
          << error.what();
    }
    return;
  }
  const ReadFile read = read_file(file);
  EXPECT_TRUE(read.complete) << GetParam();
  EXPECT_FALSE(read.truncated) << *read.truncated;
  EXPECT_EQ(read.library, "@mcap/core for wheeltec's tests");
  ASSERT_EQ(read.messages.size(), expect["messages"].size());
  for (std::size_t i = 0; i < read.messages.size(); ++i) {
    const auto& message = read.messages[i];
    const auto& wanted = expect["messages"][i];
    ASSERT_EQ(read.channels.at(message.channel_id).topic, wanted["topic"]) << i;
    ASSERT_EQ(std::to_string(message.log_time), wanted["log_time"]) << i;
    ASSERT_EQ(std::string(reinterpret_cast<const char*>(message.data.data()), message.data.size()), wanted["data"])
        << i;
    ASSERT_EQ(message.sequence, i);
  }
  const auto* events = read.channel_of_topic("/events");
  ASSERT_NE(events, nullptr);
  EXPECT_EQ(events->schema_id, 0);
  EXPECT_EQ(events->metadata.at("source"), "npm");
  ASSERT_EQ(read.metadata.size(), 1u);
  EXPECT_EQ(read.metadata[0].name, "wheeltec");
  EXPECT_EQ(nlohmann::json(read.metadata[0].metadata), expect["metadata"]["wheeltec"]);

  std::size_t previous = 0;
  for (std::size_t size = 60; size < file.size(); size += 7) {
    const ReadFile cut = read_file(ByteView(file.data(), size));
    ASSERT_TRUE(cut.truncated) << size;
    ASSERT_GE(cut.messages.size(), previous) << size;
    previous = cut.messages.size();
  }
}

INSTANTIATE_TEST_SUITE_P(Mcap, NpmFile,
                         ::testing::Values("zstd-chunks", "plain-chunks", "no-chunks", "no-summary", "lz4"),
                         [](const auto& info) {
                           std::string name = info.param;
                           for (char& c : name) c = c == '-' ? '_' : c;
                           return name;
                         });

}  // namespace
