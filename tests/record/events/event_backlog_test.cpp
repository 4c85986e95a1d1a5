// A subscriber that never reads its events (spec section 10, as for telemetry in section 2):
// its backlog is bounded, its events are dropped and counted (stats api.events_dropped), never
// coalesced, while the daemon keeps serving the other clients, every event to those that
// read, and driving.

#include <gtest/gtest.h>

#include <string>
#include <thread>

#include "event_watch.hpp"

namespace record_tests {
namespace {

using EventsBacklog = EventsTest;

std::uint64_t events_dropped(RpcConnection& client) { return client.call("stats")["api"]["events_dropped"]; }

TEST_F(EventsBacklog, ANonReaderLosesEventsCountedWhileOthersGetEveryOneAndDrivingGoesOn) {
  start();
  EventWatch& reader = watch();
  auto lazy = connect();
  EXPECT_EQ(lazy.call("subscribe", {{"topics", {"events"}}}), Json({{"topics", {"events"}}}));
  // From here on `lazy` is never read.
  auto marker = connect();
  auto driver = connect();
  auto stats = connect();
  EXPECT_EQ(events_dropped(stats), 0u);

  // Batches of marks, pipelined; the reader takes each batch's events before the next.
  constexpr int kBatch = 100;
  const std::string padding(150, '.');
  int sent = 0;
  int batches_after_drops = 0;
  std::uint64_t dropped_first = 0;
  while (batches_after_drops < 3 && sent < 100 * kBatch) {
    const int first = sent;
    for (int i = 0; i < kBatch; ++i, ++sent) {
      const Json request = {{"jsonrpc", "2.0"}, {"id", sent}, {"method", "mark"}, {"params", {{"text", std::to_string(sent) + padding}}}};
      ASSERT_TRUE(marker.send_line(request.dump()));
    }
    for (int id = first; id < sent; ++id) {
      const auto response = marker.wait_response(id, 5s);
      ASSERT_TRUE(response && response->contains("result")) << id;
    }
    for (int id = first; id < sent; ++id) {
      const Json event = reader.next("mark", 5s);
      ASSERT_EQ(event["text"], std::to_string(id) + padding) << "the reader gets every event, in order";
    }
    const std::uint64_t dropped = events_dropped(stats);
    if (dropped > 0 && dropped_first == 0) dropped_first = dropped;
    if (dropped > 0) ++batches_after_drops;
  }
  const std::uint64_t dropped = events_dropped(stats);
  std::printf("[ figure ] %d marks: %llu events dropped for the client that does not read\n", sent,
              static_cast<unsigned long long>(dropped));
  ASSERT_GT(dropped_first, 0u) << "no event was dropped for a client that never reads, after " << sent << " events";
  EXPECT_GT(dropped, dropped_first) << "each further event is dropped for it";
  EXPECT_LT(dropped, static_cast<std::uint64_t>(sent)) << "its backlog took events until it was full";

  // Meanwhile driving goes on: the drive's frame is on the port, and its events reach the reader.
  const std::size_t from = fake_->command_count();
  ASSERT_TRUE(driver.request("drive", {{"vx", 0.15}}).contains("result"));
  EXPECT_TRUE(fake_->wait_command([](const serial_tests::CommandSeen& f) { return f.x == 150; }, 500ms, from));
  EXPECT_EQ(reader.next("drive")["vx"], 0.15);
  driver.call("stop");
  reader.next("stop");
  EXPECT_GT(events_dropped(stats), dropped) << "the drive and stop events were dropped for it too";

  // A client that stays behind for 5 s is disconnected, as for telemetry: the backlog is bounded.
  const auto deadline = std::chrono::steady_clock::now() + 8s;
  while (stats.call("stats")["clients_disconnected_slow"] == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(stats.call("stats")["clients_disconnected_slow"], 1);
  EXPECT_EQ(reader.next("disconnected", 1s)["event"], "disconnected");
  EXPECT_EQ(stats.call("version")["protocol"], 5) << "the daemon serves on";
}

}  // namespace
}  // namespace record_tests
