#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "wheeltec/frames/telemetry_record.hpp"

namespace serial_tests {

using Bytes = std::vector<std::uint8_t>;
using SteadyClock = std::chrono::steady_clock;

// An 11-byte window read from the daemon, starting at a 0x7B.
struct CommandSeen {
  std::array<std::uint8_t, 11> bytes{};
  SteadyClock::time_point time;  // when its last byte was read
  int plug = 0;                  // which pseudo-terminal it came on (1 = the first)
  bool well_formed = false;      // 7B 00 00 .. .. .. .. .. .. BCC 7D with BCC = XOR of bytes 0-8
  std::int16_t x = 0, y = 0, z = 0;
  bool zero() const { return x == 0 && y == 0 && z == 0; }
  std::string text() const;  // hex bytes
};

// A byte from the daemon outside any 11-byte window (a window starts at each 0x7B).
struct StrayByte {
  std::uint8_t value = 0;
  SteadyClock::time_point time;
  int plug = 0;
  std::size_t commands_before = 0;  // how many windows had been read before it
};

// The test's stand-in for the controller behind a USB serial adapter: the master side of a
// pseudo-terminal whose slave (set raw before it is published) appears at `link`, a symlink
// created by rename as udev would. It writes what the test asks (records, charge frames,
// junk) and, when asked, a telemetry record every 50 ms from a background thread; a reader
// thread parses what the daemon writes into 11-byte windows with their arrival times.
//
// The controller keeps a descriptor of the slave open itself, so that the master does not
// see a hang-up whenever no daemon has the port open (bytes the daemon writes stay readable
// after it closes the port). unplug() closes the master (the kernel hangs the slave up, as a
// USB unplug does) and removes the link; replug() publishes a new pseudo-terminal at the
// same link.
class FakeController {
 public:
  explicit FakeController(std::filesystem::path link);
  ~FakeController();
  FakeController(const FakeController&) = delete;
  FakeController& operator=(const FakeController&) = delete;

  const std::filesystem::path& link() const { return link_; }
  std::string slave_name() const;  // /dev/pts/N of the current plug
  int plug() const;                // 1 for the first pseudo-terminal, +1 per replug
  bool plugged() const;

  // Writes all of `bytes` (one write() when the pty takes them); throws when the daemon has
  // not read them within `timeout` or the controller is unplugged.
  void write(const Bytes& bytes, std::chrono::milliseconds timeout = std::chrono::seconds(5));
  // Writes `bytes` one byte per write(), `pause` apart.
  void dribble(const Bytes& bytes, std::chrono::milliseconds pause = std::chrono::milliseconds(2));
  std::uint64_t bytes_written() const { return bytes_written_; }

  // The background telemetry: a record every `period` built from `telemetry()` (while
  // unplugged: from the next replug()); it carries on across unplug() and replug().
  void start_telemetry(std::chrono::milliseconds period = std::chrono::milliseconds(50));
  void stop_telemetry();
  void set_telemetry(const wheeltec::RawTelemetry& raw);
  wheeltec::RawTelemetry telemetry() const;
  std::uint64_t records_sent() const { return records_sent_; }
  // From now on the background records' measured velocities (vx, vy, vz) are the last
  // well-formed command's X, Y, Z: a chassis whose wheels do exactly what they are told,
  // so that the daemon's odometry is known. The rest of the record is telemetry()'s.
  void follow_commands(bool follow = true) { follow_commands_ = follow; }

  // What the daemon wrote.
  std::vector<CommandSeen> commands() const;
  std::size_t command_count() const;
  std::vector<StrayByte> stray_bytes() const;
  std::uint64_t bytes_read() const { return bytes_read_; }
  // The first window (at index >= from) that satisfies `predicate`, waiting up to `timeout`;
  // its index in commands() is stored in `index` when given.
  std::optional<CommandSeen> wait_command(const std::function<bool(const CommandSeen&)>& predicate,
                                          std::chrono::milliseconds timeout, std::size_t from = 0,
                                          std::size_t* index = nullptr);
  // Waits until at least `count` windows have been read.
  bool wait_command_count(std::size_t count, std::chrono::milliseconds timeout);
  // Waits until nothing has been read for `quiet` (at most `timeout`); true when it was quiet.
  bool wait_quiet(std::chrono::milliseconds quiet, std::chrono::milliseconds timeout);

  // The USB cable: close the master (hang-up) and remove the link; publish a new one.
  void unplug();
  void replug();

 private:
  void open_pty();
  void close_pty();
  void start_threads();
  void stop_threads();
  void reader_loop();
  void telemetry_loop(std::chrono::milliseconds period);
  void parse(const std::uint8_t* data, std::size_t size, SteadyClock::time_point time);
  void write_locked(const std::uint8_t* data, std::size_t size, std::chrono::milliseconds timeout);

  std::filesystem::path link_;
  int master_ = -1;
  int slave_keeper_ = -1;
  std::string slave_name_;
  int plug_ = 0;

  std::mutex write_mutex_;  // one writer on the master at a time, whole frames
  std::atomic<std::uint64_t> bytes_written_{0};
  std::atomic<std::uint64_t> records_sent_{0};

  mutable std::mutex mutex_;  // guards what follows
  std::condition_variable changed_;
  std::vector<CommandSeen> commands_;
  std::vector<StrayByte> stray_;
  std::array<std::uint8_t, 11> window_{};
  std::size_t filled_ = 0;
  SteadyClock::time_point last_read_ = SteadyClock::now();
  wheeltec::RawTelemetry telemetry_;
  std::atomic<std::uint64_t> bytes_read_{0};

  std::atomic<bool> stop_reader_{false};
  std::thread reader_;
  std::atomic<bool> follow_commands_{false};
  std::optional<CommandSeen> last_command_;  // the last well-formed one; guarded by mutex_
  std::atomic<bool> stop_telemetry_{false};
  std::thread telemetry_thread_;
  std::optional<std::chrono::milliseconds> telemetry_period_;
};

// A record with the given measured vx (mm/s) and flag_stop, the rest of a chassis at rest.
wheeltec::RawTelemetry resting_record(std::int16_t vx_mm_s = 0, bool flag_stop = false);
Bytes record_bytes(const wheeltec::RawTelemetry& raw);

}  // namespace serial_tests
