#include "wheeltec/frames/line_framer.hpp"

#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace wheeltec {
namespace {

using Next = LineFramer::Next;

std::vector<std::string> take_lines(LineFramer& framer) {
  std::vector<std::string> lines;
  while (framer.next() == Next::line) {
    lines.emplace_back(framer.line());
    framer.pop();
  }
  return lines;
}

TEST(LineFramer, EmptyInputNeedsMore) {
  LineFramer framer(16);
  EXPECT_EQ(framer.next(), Next::incomplete);
}

TEST(LineFramer, SplitsLinesWithoutTheirNewline) {
  LineFramer framer(16);
  framer.append("one\ntwo\n\nthree");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"one", "two", ""}));
  EXPECT_EQ(framer.next(), Next::incomplete);
}

TEST(LineFramer, JoinsALineReceivedInPieces) {
  LineFramer framer(16);
  framer.append("{\"a\"");
  EXPECT_EQ(framer.next(), Next::incomplete);
  framer.append(":1");
  EXPECT_EQ(framer.next(), Next::incomplete);
  framer.append("}\nnext");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"{\"a\":1}"}));
  framer.append("\n");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"next"}));
}

TEST(LineFramer, NextDoesNotTakeTheLine) {
  LineFramer framer(16);
  framer.append("a\nb\n");
  EXPECT_EQ(framer.next(), Next::line);
  EXPECT_EQ(framer.next(), Next::line);
  EXPECT_EQ(framer.line(), "a");
  framer.pop();
  EXPECT_EQ(framer.line(), "b");
}

TEST(LineFramer, ALineOfTheMaximumLengthIsALine) {
  LineFramer framer(4);
  framer.append("abcd");
  EXPECT_EQ(framer.next(), Next::incomplete);
  framer.append("\n");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"abcd"}));
}

TEST(LineFramer, AnUnterminatedLineOverTheMaximumIsTooLong) {
  LineFramer framer(4);
  framer.append("abcde");
  EXPECT_EQ(framer.next(), Next::too_long);
}

TEST(LineFramer, ACompleteLineOverTheMaximumIsTooLong) {
  LineFramer framer(4);
  framer.append("ok\nabcde\nok\n");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"ok"}));
  EXPECT_EQ(framer.next(), Next::too_long);
}

TEST(LineFramer, TheRestOfAFinishedStreamIsItsLastLine) {
  LineFramer framer(16);
  framer.append("one\ntwo");
  framer.finish();
  EXPECT_TRUE(framer.finished());
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"one", "two"}));
  EXPECT_EQ(framer.next(), Next::end);
}

TEST(LineFramer, AFinishedStreamEndingWithANewlineHasNoEmptyLastLine) {
  LineFramer framer(16);
  framer.append("one\n");
  framer.finish();
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"one"}));
  EXPECT_EQ(framer.next(), Next::end);
}

TEST(LineFramer, DiscardDropsThePendingInputButNotTheEnd) {
  LineFramer framer(16);
  framer.append("one\ntwo");
  framer.finish();
  framer.discard();
  EXPECT_TRUE(framer.finished());
  EXPECT_EQ(framer.next(), Next::end);
}

TEST(LineFramer, AppendingAfterTakenLinesKeepsThePendingOnes) {
  LineFramer framer(8);
  framer.append("1234567\nabc");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"1234567"}));
  // The taken line no longer counts towards the maximum of the pending one.
  framer.append("defgh\n");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"abcdefgh"}));
  framer.append("x\ny\n");
  EXPECT_EQ(take_lines(framer), (std::vector<std::string>{"x", "y"}));
}

}  // namespace
}  // namespace wheeltec
