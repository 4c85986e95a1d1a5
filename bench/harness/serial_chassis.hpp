#pragma once

// The benchmark as the chassis' controller on a serial line, beside PtyEndpoint: the
// records that keep a daemon's chassis online, and the wait until the daemon says so.

#include <condition_variable>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "child_program.hpp"
#include "pty_endpoint.hpp"

namespace bench {

// Records with flag_stop clear (bench_record(n)) written on `line` at `hz` from a thread of
// its own while it lives, as the controller sends them. PtyEndpoint::write shares nothing
// with its reads, so the benchmark may await command frames meanwhile.
class RecordStream {
 public:
  explicit RecordStream(PtyEndpoint& line, double hz = 20.0);
  ~RecordStream();
  RecordStream(const RecordStream&) = delete;
  RecordStream& operator=(const RecordStream&) = delete;

  // Why the stream stopped before its end (a write that failed), if it did.
  std::optional<std::string> failure() const;

 private:
  void run(double hz);

  PtyEndpoint& line_;
  mutable std::mutex mutex_;
  std::condition_variable stop_requested_;
  bool stopping_ = false;
  std::optional<std::string> failure_;
  std::thread thread_;
};

// Waits until `status` says the link is up and the chassis online and `ready` (records must
// be arriving meanwhile); throws with the last status and the daemon's log after timeout_ms.
void wait_until_ready(const std::filesystem::path& socket, ChildProgram& daemon, int timeout_ms = 5000);

}  // namespace bench
