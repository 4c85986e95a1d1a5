#include "wheeltec/mcap/registry.hpp"

#include <gtest/gtest.h>

#include "mcap_records.hpp"
#include "mcap_test_support.hpp"

namespace {

using namespace mcap_test;
using namespace wheeltec::mcap;

TEST(Registry, IdsCountFromOneInTheOrderAdded) {
  const auto s = mcap_test::sample_channels();
  EXPECT_EQ(s.telemetry, 1);
  EXPECT_EQ(s.tf, 5);
  EXPECT_EQ(s.registry.schemas().size(), 5u);
  ASSERT_NE(s.registry.find_channel(s.events), nullptr);
  EXPECT_EQ(s.registry.find_channel(s.events)->topic, "/events");
  EXPECT_EQ(s.registry.find_schema(3)->name, "wheeltec.Event");
  EXPECT_EQ(s.registry.find_channel(0), nullptr);
  EXPECT_EQ(s.registry.find_channel(6), nullptr);
  EXPECT_EQ(s.registry.find_schema(0), nullptr);
}

TEST(Registry, ChannelOfAnUnknownSchemaIsRefused) {
  Registry registry;
  EXPECT_THROW(registry.add_channel(1, "/a", "json"), Error);
  EXPECT_TRUE(registry.channels().empty());
  EXPECT_EQ(registry.add_channel(0, "/a", "json"), 1) << "schema id 0: no schema";
}

TEST(Registry, HoldsAsManyChannelsAsAUint16Counts) {
  Registry registry;
  for (int i = 0; i < 65535; ++i) registry.add_channel(0, "/c", "json");
  EXPECT_EQ(registry.channels().back().id, 65535);
  EXPECT_THROW(registry.add_channel(0, "/c", "json"), Error);
  EXPECT_EQ(registry.channels().size(), 65535u);
}

TEST(Registry, RecordsAreEncodedAsTheSpecificationSays) {
  const auto s = mcap_test::sample_channels();
  const auto schema = split_records(s.registry.schema_record(3), 0);
  ASSERT_EQ(schema.size(), 1u);
  EXPECT_EQ(schema[0].opcode, mcap_test::kSchema);
  FieldReader schema_fields(schema[0].content);
  EXPECT_EQ(schema_fields.u16(), 3);
  EXPECT_EQ(schema_fields.string(), "wheeltec.Event");
  EXPECT_EQ(schema_fields.string(), "jsonschema");
  EXPECT_EQ(mcap_test::as_text(schema_fields.bytes32()), R"({"type":"object"})");
  EXPECT_TRUE(schema_fields.at_end());

  const auto channel = split_records(s.registry.channel_record(s.events), 0);
  ASSERT_EQ(channel.size(), 1u);
  EXPECT_EQ(channel[0].opcode, mcap_test::kChannel);
  FieldReader channel_fields(channel[0].content);
  EXPECT_EQ(channel_fields.u16(), s.events);
  EXPECT_EQ(channel_fields.u16(), 3);
  EXPECT_EQ(channel_fields.string(), "/events");
  EXPECT_EQ(channel_fields.string(), "json");
  EXPECT_EQ(channel_fields.string_map(), (std::map<std::string, std::string>{{"source", "wheeltecd"}}));
  EXPECT_TRUE(channel_fields.at_end());
}

TEST(Registry, FingerprintFollowsWhatWasAdded) {
  EXPECT_EQ(mcap_test::sample_channels().registry.fingerprint(), mcap_test::sample_channels().registry.fingerprint());
  auto other = mcap_test::sample_channels().registry;
  const auto before = other.fingerprint();
  other.add_channel(0, "/extra", "json");
  EXPECT_NE(other.fingerprint(), before);

  Registry a;
  Registry b;
  a.add_schema("s", "jsonschema", text_bytes("{}"));
  b.add_schema("s", "jsonschema", text_bytes("[]"));
  EXPECT_NE(a.fingerprint(), b.fingerprint());
}

}  // namespace
