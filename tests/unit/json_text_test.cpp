#include <string>

#include <gtest/gtest.h>

#include "wheeltec/config/json_text.hpp"

namespace wheeltec::json_text {
namespace {

using Reason = Refusal::Reason;

TEST(JsonTextStrictRead, AWellFormedTextIsReadWhole) {
  const StrictRead read = read_strict(R"({"vx":0.2,"a":[1,{"b":2}]})", kMaxMessageDepth);
  EXPECT_FALSE(read.refusal);
  EXPECT_EQ(read.document["a"][1]["b"], 2);
}

TEST(JsonTextStrictRead, TextThatDoesNotParseIsRefusedBeforeAKeyGivenTwice) {
  const StrictRead read = read_strict(R"({"a":1,"a":2)", 8);
  ASSERT_TRUE(read.refusal);
  EXPECT_EQ(read.refusal->reason, Reason::not_json);
  EXPECT_TRUE(read.syntax_error);
  EXPECT_TRUE(read.document.is_null());
}

TEST(JsonTextStrictRead, NestingTooDeepIsNamedEvenWhenTheTextThenDoesNotParse) {
  const StrictRead read = read_strict(std::string(100, '['), 8);
  ASSERT_TRUE(read.refusal);
  EXPECT_EQ(read.refusal->reason, Reason::too_deep);
  EXPECT_TRUE(read.syntax_error) << "the syntax error is kept for who answers it first";
}

TEST(JsonTextStrictRead, NestingIsLimitedAndNamedBeforeDuplicates) {
  EXPECT_FALSE(read_strict("[[[[[[[[]]]]]]]]", 8).refusal);
  const StrictRead read = read_strict(R"({"a":1,"a":[[[[[[[[]]]]]]]]})", 8);
  ASSERT_TRUE(read.refusal);
  EXPECT_EQ(read.refusal->reason, Reason::too_deep);
  EXPECT_EQ(read.refusal->message, "nested deeper than 8 levels");
}

TEST(JsonTextStrictRead, AKeyGivenTwiceIsRefusedButTheDocumentKept) {
  const StrictRead read = read_strict(R"({"id":1,"vx":0.1,"vx":"\u00ff"})", 8);
  ASSERT_TRUE(read.refusal);
  EXPECT_EQ(read.refusal->reason, Reason::duplicate_key);
  EXPECT_EQ(read.refusal->message, "duplicate key \"vx\"");
  EXPECT_EQ(read.document["id"], 1);
}

}  // namespace
}  // namespace wheeltec::json_text
