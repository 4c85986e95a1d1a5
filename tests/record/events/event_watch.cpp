#include "event_watch.hpp"

#include <stdexcept>
#include <thread>

namespace record_tests {

EventWatch::EventWatch(const SerialDaemon& daemon) : connection_(daemon.connect()) {
  const Json topics = connection_.call("subscribe", {{"topics", {"events"}}});
  if (topics != Json({{"topics", {"events"}}})) throw std::runtime_error("subscribe answered " + topics.dump());
  // The fixture's own connections (status polls while starting) are closed by now: wait
  // until the daemon has seen them go, then start the stream behind their events.
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (connection_.call("stats")["clients"] != 1) {
    if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error("other clients stay connected");
    std::this_thread::sleep_for(10ms);
  }
  sync();
}

Json EventWatch::next(std::chrono::milliseconds timeout) {
  const auto notification = connection_.wait_notification("event", timeout);
  if (!notification) throw std::runtime_error("no event within " + std::to_string(timeout.count()) + " ms");
  return (*notification)["params"];
}

Json EventWatch::next(const std::string& kind, std::chrono::milliseconds timeout) {
  Json event = next(timeout);
  if (event["event"] != kind) throw std::runtime_error("expected a " + kind + " event, got " + event.dump());
  return event;
}

void EventWatch::expect_none(std::chrono::milliseconds quiet) {
  const auto notification = connection_.wait_notification("event", quiet);
  if (notification) throw std::runtime_error("expected no event, got " + (*notification)["params"].dump());
}

void EventWatch::sync() {
  const std::string text = "sync " + std::to_string(++syncs_);
  connection_.call("mark", {{"text", text}});
  for (;;) {
    const Json event = next();
    if (event["event"] == "mark" && event["text"] == text) {
      id_ = event["client"].get<std::uint64_t>();
      return;
    }
  }
}

SerialDaemon& EventsTest::start(serial_tests::DaemonOptions options) {
  fake_->start_telemetry();
  daemon_ = &start_daemon_ready(std::move(options));
  watch_ = std::make_unique<EventWatch>(*daemon_);
  return *daemon_;
}

RpcConnection EventsTest::connect(Json* id) {
  RpcConnection client = daemon_->connect();
  const Json connected = watch_->next("connected");
  if (id != nullptr) *id = connected["client"];
  return client;
}

}  // namespace record_tests
