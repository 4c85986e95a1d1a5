#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "serial_daemon.hpp"

namespace record_tests {

using integration::Json;
using integration::RpcConnection;
using serial_tests::SerialDaemon;
using namespace std::chrono_literals;

// A connection subscribed to the daemon's events that reads them as they come. Its stream
// starts clean: the connections the fixture opened and closed before it subscribed are gone
// (their `disconnected` events, if any reached it, are skipped).
class EventWatch {
 public:
  explicit EventWatch(const SerialDaemon& daemon);

  // The next EVENT (the notification's params); throws when none comes within `timeout`
  // or, with a `kind`, when the next one is of another kind.
  Json next(std::chrono::milliseconds timeout = 2s);
  Json next(const std::string& kind, std::chrono::milliseconds timeout = 2s);
  // Throws when an event comes within `quiet`.
  void expect_none(std::chrono::milliseconds quiet);
  // Marks the stream (`mark` from this connection) and skips every event until that mark:
  // what happened before is behind, and nothing else was pending.
  void sync();

  RpcConnection& connection() { return connection_; }
  std::uint64_t id() const { return id_; }  // this connection's client id

 private:
  RpcConnection connection_;
  std::uint64_t id_ = 0;
  int syncs_ = 0;
};

using serial_tests::wall_seconds_now;

// Every events test: the fake controller sending telemetry, wheeltecd ready on it, and a
// watch of its events.
class EventsTest : public serial_tests::SerialTest {
 protected:
  SerialDaemon& start(serial_tests::DaemonOptions options = {});
  // A new connection; its client id (from its connected event) in `id` when given.
  RpcConnection connect(Json* id = nullptr);

  SerialDaemon& daemon() { return *daemon_; }
  EventWatch& watch() { return *watch_; }

 private:
  SerialDaemon* daemon_ = nullptr;
  std::unique_ptr<EventWatch> watch_;
};

}  // namespace record_tests
