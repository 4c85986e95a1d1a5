#include "incident_window.hpp"

#include <gtest/gtest.h>

#include "test_time.hpp"

namespace wheeltec::record {
namespace {

using std::chrono::minutes;
using std::chrono::seconds;

using test::t0;

FiredTrigger at(int second, Trigger trigger = Trigger::deadman) { return {trigger, t0 + seconds(second)}; }

class RecordIncidentWindow : public ::testing::Test {
 protected:
  IncidentWindow window{seconds(60), seconds(10)};  // the defaults: --before 60 --after 10
};

TEST_F(RecordIncidentWindow, ATriggerStartsAFileFromBeforeToAfterIt) {
  EXPECT_FALSE(window.recording());
  const auto result = window.on_trigger(at(0));
  EXPECT_EQ(result.change, IncidentWindow::Change::started);
  EXPECT_EQ(result.ended, std::nullopt);
  EXPECT_EQ(window.start(), t0 - seconds(60));
  EXPECT_EQ(window.end(), t0 + seconds(10));
  EXPECT_TRUE(window.covers(t0 - seconds(60)));
  EXPECT_TRUE(window.covers(t0 + seconds(10)));
  EXPECT_FALSE(window.covers(t0 - seconds(61)));
  EXPECT_FALSE(window.covers(t0 + seconds(11)));
}

TEST_F(RecordIncidentWindow, ASecondTriggerFiveSecondsLaterExtendsTheFileToTenSecondsAfterIt) {
  window.on_trigger(at(0));
  EXPECT_EQ(window.on_trigger(at(5, Trigger::mark)).change, IncidentWindow::Change::extended);
  EXPECT_EQ(window.start(), t0 - seconds(60));
  EXPECT_EQ(window.end(), t0 + seconds(15));
  EXPECT_EQ(window.on_tick(t0 + seconds(12)), std::nullopt);
  const auto done = window.on_tick(t0 + seconds(15));
  ASSERT_TRUE(done);
  EXPECT_EQ(done->triggers, (std::vector{at(0), at(5, Trigger::mark)}));
  EXPECT_EQ(done->start, t0 - seconds(60));
  EXPECT_EQ(done->end, t0 + seconds(15));
  EXPECT_FALSE(window.recording());
}

TEST_F(RecordIncidentWindow, AWindowNeverGrowsBeyondTenMinutes) {
  window.on_trigger(at(0));
  // A trigger every 5 s, each inside the window so far.
  for (int second = 5; second < 540; second += 5) {
    window.on_trigger(at(second, Trigger::refused));
    ASSERT_LE(*window.end() - *window.start(), minutes(10)) << second;
  }
  // Start 60 s before the first trigger: the file ends 540 s after it, whatever followed.
  EXPECT_EQ(window.end(), t0 + seconds(540));
  // The next one, at that end, is the first of a new file.
  const auto result = window.on_trigger(at(540, Trigger::refused));
  EXPECT_EQ(result.change, IncidentWindow::Change::started);
  ASSERT_TRUE(result.ended);
  EXPECT_EQ(result.ended->end - result.ended->start, minutes(10));
  EXPECT_EQ(result.ended->triggers.size(), 108u);
}

TEST_F(RecordIncidentWindow, TriggersAtTheLimitJoinTheList) {
  window.on_trigger(at(0));
  for (int second = 5; second <= 530; second += 5) window.on_trigger(at(second));
  EXPECT_EQ(window.end(), t0 + seconds(540));
  EXPECT_EQ(window.on_trigger(at(535, Trigger::mark)).change, IncidentWindow::Change::joined);
  const auto& recording = std::get<IncidentWindow::Recording>(window.state());
  EXPECT_EQ(recording.triggers.back(), at(535, Trigger::mark));
}

TEST_F(RecordIncidentWindow, AnEarlierTriggerJoinsWithoutShorteningTheFile) {
  window.on_trigger(at(0));
  window.on_trigger(at(8));
  EXPECT_EQ(window.on_trigger(at(3, Trigger::mark)).change, IncidentWindow::Change::joined);
  EXPECT_EQ(window.end(), t0 + seconds(18));
}

TEST_F(RecordIncidentWindow, ALongFirstWindowIsKeptWholeButNotExtended) {
  IncidentWindow long_window{seconds(600), seconds(30)};
  long_window.on_trigger(at(0));
  EXPECT_EQ(*long_window.end() - *long_window.start(), seconds(630));
  EXPECT_EQ(long_window.on_trigger(at(20)).change, IncidentWindow::Change::joined);
  EXPECT_EQ(long_window.end(), t0 + seconds(30));
}

TEST_F(RecordIncidentWindow, ATriggerAfterTheFileClosedStartsANewOne) {
  window.on_trigger(at(0));
  ASSERT_TRUE(window.on_tick(t0 + seconds(10)));
  const auto result = window.on_trigger(at(11, Trigger::offline));
  EXPECT_EQ(result.change, IncidentWindow::Change::started);
  EXPECT_EQ(result.ended, std::nullopt);
  EXPECT_EQ(window.start(), t0 - seconds(49));
  EXPECT_EQ(std::get<IncidentWindow::Recording>(window.state()).triggers, std::vector{at(11, Trigger::offline)});
}

TEST_F(RecordIncidentWindow, ATriggerPastTheEndBeforeAnyTickHandsBackTheEndedFile) {
  window.on_trigger(at(0));
  const auto result = window.on_trigger(at(10, Trigger::halted));  // at the end: not inside
  EXPECT_EQ(result.change, IncidentWindow::Change::started);
  ASSERT_TRUE(result.ended);
  EXPECT_EQ(result.ended->triggers, std::vector{at(0)});
  EXPECT_EQ(result.ended->end, t0 + seconds(10));
  EXPECT_EQ(window.start(), t0 - seconds(50));
  EXPECT_EQ(window.end(), t0 + seconds(20));
}

TEST_F(RecordIncidentWindow, DaemonLostWritesWhatItHoldsAtOnce) {
  const auto result = window.on_trigger(at(0, Trigger::daemon_lost));
  EXPECT_EQ(result.change, IncidentWindow::Change::started);
  EXPECT_EQ(window.start(), t0 - seconds(60));
  EXPECT_EQ(window.end(), t0);
  const auto done = window.on_tick(t0);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->triggers, std::vector{at(0, Trigger::daemon_lost)});
}

TEST_F(RecordIncidentWindow, DaemonLostFinishesAFileInProgress) {
  window.on_trigger(at(0));
  EXPECT_EQ(window.on_trigger(at(3, Trigger::daemon_lost)).change, IncidentWindow::Change::ends_now);
  EXPECT_EQ(window.end(), t0 + seconds(3));
  EXPECT_EQ(window.on_tick(t0 + seconds(2)), std::nullopt);
  const auto done = window.on_tick(t0 + seconds(3));
  ASSERT_TRUE(done);
  EXPECT_EQ(done->triggers, (std::vector{at(0), at(3, Trigger::daemon_lost)}));
  EXPECT_EQ(done->end, t0 + seconds(3));
}

TEST_F(RecordIncidentWindow, IdleCoversNothingAndTicksFinishNothing) {
  EXPECT_FALSE(window.covers(t0));
  EXPECT_EQ(window.start(), std::nullopt);
  EXPECT_EQ(window.end(), std::nullopt);
  EXPECT_EQ(window.on_tick(t0), std::nullopt);
}

}  // namespace
}  // namespace wheeltec::record
