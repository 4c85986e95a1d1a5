// The black box end to end in memory: what the daemon's socket would bring, at chosen
// times, into files that the MCAP test reader checks record by record.

#include "black_box.hpp"

#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <string>

#include "file_metadata.hpp"
#include "wheeltec/record/file_names.hpp"
#include "mcap_checker.hpp"

namespace wheeltec::record {
namespace {

using namespace std::chrono_literals;

// Files in memory: NAME.part while written, NAME once committed.
class MemoryStore : public FileStore {
 public:
  std::map<std::string, mcap::Bytes> files;
  bool full = false;  // writes fail as on a full disk

  std::unique_ptr<FileOutput> create(const std::string& name) override {
    files[part_name(name)].clear();
    return std::make_unique<MemoryFile>(*this, name);
  }
  std::vector<StoredFile> list() const override {
    std::vector<StoredFile> stored;
    for (const auto& [name, bytes] : files) stored.push_back({name, bytes.size()});
    return stored;
  }
  void remove(const std::string& name) override { files.erase(name); }

  std::vector<std::string> whole_names() const {
    std::vector<std::string> names;
    for (const auto& [name, bytes] : files) {
      if (name.ends_with(kFileSuffix)) names.push_back(name);
    }
    return names;
  }

 private:
  class MemoryFile : public FileOutput {
   public:
    MemoryFile(MemoryStore& store, std::string name) : store_(store), name_(std::move(name)) {}
    void write(mcap::ByteView bytes) override {
      if (store_.full) throw std::runtime_error("No space left on device");
      auto& file = store_.files.at(part_name(name_));
      file.insert(file.end(), bytes.begin(), bytes.end());
    }
    void commit() override {
      auto node = store_.files.extract(part_name(name_));
      node.key() = name_;
      store_.files.insert(std::move(node));
    }

   private:
    MemoryStore& store_;
    std::string name_;
  };
};

const RealtimeNanos kStart = RealtimeNanos(1795552460s);

double seconds(RealtimeNanos time) { return std::chrono::duration<double>(time.time_since_epoch()).count(); }

Json record_at(RealtimeNanos time, int seq) {
  return Json{{"seq", seq},
              {"time", seconds(time)},
              {"velocity", {{"vx", 0.2}, {"vy", 0.0}, {"wz", 0.0}}},
              {"odom", {{"x", 0.01 * seq}, {"y", 0.0}, {"yaw", 0.0}}}};
}

Json status_ready() {
  return Json::parse(R"({"bus":{"interface":"/dev/ttyACM0","state":"up","transport":"serial"},
    "chassis":{"battery_low":false,"battery_v":12.0,"commands_ignored":false,"online":true,"phase":"ready",
    "stopped":false,"type":"mecanum"},"control":{"enabled":true,"owner":null},"version":"0.1.0"})");
}

Json event_at(RealtimeNanos time, const std::string& kind) {
  return Json{{"time", seconds(time)}, {"event", kind}, {"client", 3}};
}

// Drives a black box through time: 20 telemetry records a second and a tick every 250 ms.
class Feed {
 public:
  Feed(BlackBox& box, RealtimeNanos start) : box_(box), now_(start) {}

  void run_for(std::chrono::nanoseconds span) {
    const RealtimeNanos until = now_ + span;
    while (now_ < until) {
      now_ += 50ms;
      box_.on_telemetry(record_at(now_, ++seq_), now_);
      if (++steps_ % 5 == 0) box_.on_tick(now_);
    }
  }
  // An event of this kind from client 3, now; returns its time.
  RealtimeNanos event(const std::string& kind) {
    box_.on_event(event_at(now_, kind), now_);
    return now_;
  }
  void status(const Json& status) { box_.on_status(status, now_); }
  // The chassis ready, then `span` of records.
  void ready_for(std::chrono::nanoseconds span) {
    status(status_ready());
    run_for(span);
  }
  RealtimeNanos now() const { return now_; }
  int records() const { return seq_; }

 private:
  BlackBox& box_;
  RealtimeNanos now_;
  int seq_ = 0;
  int steps_ = 0;
};

// A black box on a store in memory, and the feed that drives it.
struct Rig {
  explicit Rig(const BlackBoxSettings& settings) : box(settings, store), feed(box, kStart) {}
  MemoryStore store;
  BlackBox box;
  Feed feed;
};

BlackBoxSettings settings(std::chrono::nanoseconds before, std::chrono::nanoseconds after) {
  BlackBoxSettings s;
  s.before = before;
  s.after = after;
  return s;
}

std::vector<mcap_test::ReadMessage> on_channel(const mcap_test::ReadFile& file, Channel channel) {
  std::vector<mcap_test::ReadMessage> messages;
  for (const auto& message : file.messages) {
    if (message.channel_id == static_cast<int>(channel) + 1) messages.push_back(message);
  }
  return messages;
}

RealtimeNanos log_time_of(const mcap_test::ReadMessage& message) {
  return RealtimeNanos(std::chrono::nanoseconds(message.log_time));
}

TEST(BlackBox, AMarkWritesOneFileFromBeforeTheTriggerToAfterIt) {
  Rig rig(settings(10s, 2s));
  auto& [store, box, feed] = rig;
  feed.ready_for(20s);
  const RealtimeNanos marked = feed.event("mark");
  feed.run_for(5s);

  const std::string name = file_name(marked, Trigger::mark);
  ASSERT_EQ(store.whole_names(), std::vector<std::string>{name});
  const mcap_test::ReadFile file = mcap_test::check_mcap(store.files.at(name));
  const auto telemetry = on_channel(file, Channel::telemetry);
  ASSERT_FALSE(telemetry.empty());
  // The ring holds whole chunks of a second: the file starts up to one earlier.
  EXPECT_LE(log_time_of(telemetry.front()), marked - 10s);
  EXPECT_GE(log_time_of(telemetry.front()), marked - 11s);
  EXPECT_GE(log_time_of(telemetry.back()), marked + 2s);
  EXPECT_LE(log_time_of(telemetry.back()), marked + 2s + 300ms);
  EXPECT_EQ(on_channel(file, Channel::odom).size(), telemetry.size());
  EXPECT_EQ(on_channel(file, Channel::tf).size(), telemetry.size());
  // The status before the first message comes first, though it was received long before.
  const auto status = on_channel(file, Channel::status);
  ASSERT_EQ(status.size(), 1u);
  EXPECT_EQ(Json::parse(status.front().payload), status_ready());
  ASSERT_EQ(on_channel(file, Channel::events).size(), 1u);
  ASSERT_EQ(file.metadata.size(), 1u);
  EXPECT_EQ(file.metadata[0].first, kMetadataName);
  EXPECT_EQ(file.metadata[0].second.at("triggers"), triggers_json({{Trigger::mark, marked}}));
  EXPECT_EQ(file.metadata[0].second.at("transport"), "serial");
}

TEST(BlackBox, ASecondTriggerInsideTheWindowExtendsTheSameFile) {
  Rig rig(settings(5s, 2s));
  auto& [store, box, feed] = rig;
  feed.ready_for(10s);
  const RealtimeNanos first = feed.event("mark");
  feed.run_for(1500ms);
  const RealtimeNanos second = feed.event("deadman");
  feed.run_for(10s);

  ASSERT_EQ(store.whole_names(), std::vector<std::string>{file_name(first, Trigger::mark)});
  const auto file = mcap_test::check_mcap(store.files.begin()->second);
  EXPECT_GE(log_time_of(on_channel(file, Channel::telemetry).back()), second + 2s);
  EXPECT_EQ(file.metadata.at(0).second.at("triggers"),
            triggers_json({{Trigger::mark, first}, {Trigger::deadman, second}}));
}

TEST(BlackBox, AnEmergencyStopWritesAnEstopFile) {
  Rig rig(settings(3s, 1s));
  auto& [store, box, feed] = rig;
  feed.ready_for(4s);
  Json estop = event_at(feed.now(), "estop");
  estop["source"] = "client";
  estop["reason"] = "operator pressed E-STOP";
  const RealtimeNanos latched = feed.now();
  box.on_event(estop, latched);
  feed.run_for(500ms);
  Json release = event_at(feed.now(), "release");  // no trigger, but recorded in the same file
  box.on_event(release, feed.now());
  feed.run_for(2s);

  const std::string name = file_name(latched, Trigger::estop);
  ASSERT_EQ(store.whole_names(), std::vector<std::string>{name});
  EXPECT_TRUE(name.ends_with("-estop.mcap")) << name;
  const auto file = mcap_test::check_mcap(store.files.at(name));
  const auto events = on_channel(file, Channel::events);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(Json::parse(events[0].payload), estop);
  EXPECT_EQ(Json::parse(events[1].payload)["event"], "release");
  EXPECT_EQ(file.metadata.at(0).second.at("triggers"), triggers_json({{Trigger::estop, latched}}));
}

TEST(BlackBox, ATriggerAfterTheWindowStartsASecondFile) {
  Rig rig(settings(2s, 1s));
  auto& [store, box, feed] = rig;
  feed.run_for(3s);
  feed.event("mark");
  feed.run_for(3s);
  feed.event("deadman");
  feed.run_for(3s);
  EXPECT_EQ(store.whole_names().size(), 2u);
}

TEST(BlackBox, ALostDaemonIsWrittenAtOnce) {
  Rig rig(settings(5s, 10s));
  auto& [store, box, feed] = rig;
  feed.ready_for(8s);
  box.on_daemon_lost(feed.now());
  ASSERT_EQ(store.whole_names(), std::vector<std::string>{file_name(feed.now(), Trigger::daemon_lost)});
  const auto file = mcap_test::check_mcap(store.files.begin()->second);
  EXPECT_EQ(log_time_of(on_channel(file, Channel::telemetry).back()), feed.now());
}

TEST(BlackBox, FinishWritesTheFileInProgressWithWhatItHas) {
  Rig rig(settings(5s, 10s));
  auto& [store, box, feed] = rig;
  feed.run_for(6s);
  const RealtimeNanos marked = feed.event("mark");
  feed.run_for(2s);
  EXPECT_TRUE(store.whole_names().empty());
  box.finish(feed.now());
  ASSERT_EQ(store.whole_names(), std::vector<std::string>{file_name(marked, Trigger::mark)});
  const auto file = mcap_test::check_mcap(store.files.begin()->second);
  EXPECT_EQ(log_time_of(on_channel(file, Channel::telemetry).back()), feed.now());
}

TEST(BlackBox, TriggersThatAreOffWriteNothing) {
  MemoryStore store;
  BlackBoxSettings off = settings(5s, 1s);
  off.triggers.erase(Trigger::mark);
  BlackBox box(off, store);
  Feed feed(box, kStart);
  feed.run_for(3s);
  feed.event("mark");
  feed.event("refused");  // off by default
  feed.run_for(3s);
  box.finish(feed.now());
  EXPECT_TRUE(store.files.empty());
}

TEST(BlackBox, ContinuousFilesMeetWithoutGapOrRepeat) {
  MemoryStore store;
  BlackBoxSettings continuous = settings(5s, 1s);
  continuous.continuous_split = 5s;
  BlackBox box(continuous, store);
  Feed feed(box, kStart);
  feed.run_for(23s);
  box.finish(feed.now());

  std::vector<int> sequence;
  for (const std::string& name : store.whole_names()) {  // in time order: the names sort so
    EXPECT_TRUE(name.ends_with("-continuous.mcap")) << name;
    for (const auto& message : on_channel(mcap_test::check_mcap(store.files.at(name)), Channel::telemetry)) {
      sequence.push_back(Json::parse(message.payload).at("seq").get<int>());
    }
  }
  EXPECT_EQ(store.whole_names().size(), 5u);
  ASSERT_EQ(sequence.size(), static_cast<std::size_t>(feed.records()));
  for (std::size_t i = 0; i < sequence.size(); ++i) ASSERT_EQ(sequence[i], static_cast<int>(i) + 1);
}

TEST(BlackBox, RetentionDeletesTheOldestFilesAndKeepsTheNewOne) {
  MemoryStore store;
  store.files["20251127T000000Z-mark.mcap"] = mcap::Bytes(40'000);
  store.files["20251128T000000Z-mark.mcap"] = mcap::Bytes(40'000);
  store.files["notes.txt"] = mcap::Bytes(1'000'000);  // not the recorder's: neither counted nor touched
  BlackBoxSettings small = settings(3s, 1s);
  small.max_bytes = 100'000;
  BlackBox box(small, store);
  Feed feed(box, kStart);
  feed.run_for(4s);
  feed.event("mark");
  feed.run_for(2s);
  const std::string newest = file_name(feed.now() - 2s, Trigger::mark);
  ASSERT_TRUE(store.files.contains(newest));
  const std::uint64_t newest_bytes = store.files.at(newest).size();
  ASSERT_LT(newest_bytes, 60'000u);
  EXPECT_FALSE(store.files.contains("20251127T000000Z-mark.mcap"));
  EXPECT_TRUE(store.files.contains("20251128T000000Z-mark.mcap"));
  EXPECT_TRUE(store.files.contains("notes.txt"));
}

// Issue 41 item 5: with a limit below one incident's size, each incident was deleted as
// soon as it was written. Now the newest is kept, and the one before it goes.
TEST(BlackBox, ALimitBelowOneFileKeepsTheNewestIncident) {
  BlackBoxSettings tiny = settings(2s, 1s);
  tiny.max_bytes = 1'000;
  Rig rig(tiny);
  auto& [store, box, feed] = rig;
  feed.run_for(3s);
  const RealtimeNanos first = feed.event("mark");
  feed.run_for(2s);
  const std::string first_name = file_name(first, Trigger::mark);
  ASSERT_EQ(store.whole_names(), std::vector<std::string>{first_name});
  EXPECT_GT(store.files.at(first_name).size(), tiny.max_bytes);
  mcap_test::check_mcap(store.files.at(first_name));

  feed.run_for(2s);
  const RealtimeNanos second = feed.event("mark");
  feed.run_for(500ms);  // while the second is written, the first is still the newest finished one
  EXPECT_EQ(store.whole_names(), std::vector<std::string>{first_name});
  feed.run_for(1500ms);
  EXPECT_EQ(store.whole_names(), std::vector<std::string>{file_name(second, Trigger::mark)});
  EXPECT_EQ(box.files_written(), 2u);
}

TEST(BlackBox, AFileThatCannotBeWrittenIsDroppedAndTheNextOneIsWhole) {
  Rig rig(settings(2s, 1s));
  auto& [store, box, feed] = rig;
  feed.run_for(3s);
  store.full = true;
  feed.event("mark");
  feed.run_for(3s);
  EXPECT_TRUE(store.whole_names().empty());
  store.full = false;
  feed.event("mark");
  feed.run_for(3s);
  ASSERT_EQ(store.whole_names().size(), 1u);
  mcap_test::check_mcap(store.files.at(store.whole_names().front()));
}

TEST(BlackBox, TheRingKeepsOnlyTheLastSeconds) {
  Rig rig(settings(5s, 1s));
  auto& [store, box, feed] = rig;
  feed.run_for(60s);
  EXPECT_LE(box.ring_chunks(), 7u);  // 5 s of one-second chunks, and the ones at its edges
  EXPECT_GT(box.ring_bytes(), 0u);
}

}  // namespace
}  // namespace wheeltec::record
