#include "fake_controller.hpp"

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace serial_tests {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::runtime_error("fake controller: " + what + ": " + std::strerror(errno));
}

std::uint8_t xor_of(const std::uint8_t* bytes, std::size_t n) {
  std::uint8_t x = 0;
  for (std::size_t i = 0; i < n; ++i) x ^= bytes[i];
  return x;
}

std::int16_t be16(const std::uint8_t* p) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>((p[0] << 8) | p[1]));
}

}  // namespace

std::string CommandSeen::text() const {
  std::string out;
  char hex[4];
  for (const auto b : bytes) {
    std::snprintf(hex, sizeof hex, "%02X ", b);
    out += hex;
  }
  if (!out.empty()) out.pop_back();
  return out;
}

wheeltec::RawTelemetry resting_record(std::int16_t vx_mm_s, bool flag_stop) {
  wheeltec::RawTelemetry raw;
  raw.flag_stop = flag_stop ? 1 : 0;
  raw.vx = vx_mm_s;
  raw.accel_z = 16403;  // 1 g
  raw.battery_mv = 22500;
  return raw;
}

Bytes record_bytes(const wheeltec::RawTelemetry& raw) {
  const auto record = wheeltec::encode_record(raw);
  return Bytes(record.begin(), record.end());
}

FakeController::FakeController(std::filesystem::path link) : link_(std::move(link)) {
  telemetry_ = resting_record();
  open_pty();
  start_threads();
}

FakeController::~FakeController() {
  stop_threads();
  close_pty();
}

std::string FakeController::slave_name() const {
  std::lock_guard lock(mutex_);
  return slave_name_;
}

int FakeController::plug() const {
  std::lock_guard lock(mutex_);
  return plug_;
}

bool FakeController::plugged() const { return master_ >= 0; }

void FakeController::open_pty() {
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master < 0) fail("posix_openpt");
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0) {
    ::close(master);
    fail("grantpt/unlockpt");
  }
  char name[128];
  if (::ptsname_r(master, name, sizeof name) != 0) {
    ::close(master);
    fail("ptsname_r");
  }
  const int slave = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave < 0) {
    ::close(master);
    fail(std::string("open ") + name);
  }
  // Raw before it is published: no ICRNL, IXON, ECHO or line editing to mangle binary frames.
  termios tio{};
  if (::tcgetattr(slave, &tio) != 0) fail("tcgetattr");
  ::cfmakeraw(&tio);
  ::cfsetispeed(&tio, B115200);
  ::cfsetospeed(&tio, B115200);
  tio.c_cflag |= CLOCAL | CREAD;
  if (::tcsetattr(slave, TCSANOW, &tio) != 0) fail("tcsetattr");
  ::fcntl(master, F_SETFL, ::fcntl(master, F_GETFL) | O_NONBLOCK);

  // Publish by rename, as udev re-creates a symlink.
  const std::filesystem::path temporary = link_.string() + ".new";
  std::error_code ignored;
  std::filesystem::remove(temporary, ignored);
  if (::symlink(name, temporary.c_str()) != 0) fail("symlink " + temporary.string());
  if (::rename(temporary.c_str(), link_.c_str()) != 0) fail("rename to " + link_.string());

  std::lock_guard lock(mutex_);
  master_ = master;
  slave_keeper_ = slave;
  slave_name_ = name;
  ++plug_;
  filled_ = 0;
}

void FakeController::close_pty() {
  if (master_ < 0) return;
  std::error_code ignored;
  std::filesystem::remove(link_, ignored);
  ::close(master_);  // the kernel hangs up every open descriptor of the slave
  ::close(slave_keeper_);
  std::lock_guard lock(mutex_);
  master_ = -1;
  slave_keeper_ = -1;
  filled_ = 0;
}

void FakeController::start_threads() {
  stop_reader_ = false;
  reader_ = std::thread([this] { reader_loop(); });
  if (telemetry_period_) {
    stop_telemetry_ = false;
    const auto period = *telemetry_period_;
    telemetry_thread_ = std::thread([this, period] { telemetry_loop(period); });
  }
}

void FakeController::stop_threads() {
  stop_telemetry_ = true;
  if (telemetry_thread_.joinable()) telemetry_thread_.join();
  stop_reader_ = true;
  if (reader_.joinable()) reader_.join();
}

void FakeController::unplug() {
  if (master_ < 0) throw std::logic_error("fake controller: unplug while unplugged");
  stop_threads();
  close_pty();
}

void FakeController::replug() {
  if (master_ >= 0) throw std::logic_error("fake controller: replug while plugged");
  open_pty();
  start_threads();
}

void FakeController::start_telemetry(std::chrono::milliseconds period) {
  stop_telemetry();
  telemetry_period_ = period;
  if (master_ < 0) return;  // from the next replug()
  stop_telemetry_ = false;
  telemetry_thread_ = std::thread([this, period] { telemetry_loop(period); });
}

void FakeController::stop_telemetry() {
  stop_telemetry_ = true;
  if (telemetry_thread_.joinable()) telemetry_thread_.join();
  telemetry_period_.reset();
}

void FakeController::set_telemetry(const wheeltec::RawTelemetry& raw) {
  std::lock_guard lock(mutex_);
  telemetry_ = raw;
}

wheeltec::RawTelemetry FakeController::telemetry() const {
  std::lock_guard lock(mutex_);
  return telemetry_;
}

void FakeController::telemetry_loop(std::chrono::milliseconds period) {
  auto next = SteadyClock::now();
  while (!stop_telemetry_) {
    wheeltec::RawTelemetry raw = telemetry();
    if (follow_commands_) {
      std::lock_guard lock(mutex_);
      raw.vx = last_command_ ? last_command_->x : 0;
      raw.vy = last_command_ ? last_command_->y : 0;
      raw.vz = last_command_ ? last_command_->z : 0;
    }
    const Bytes record = record_bytes(raw);
    try {
      std::lock_guard lock(write_mutex_);
      write_locked(record.data(), record.size(), std::chrono::milliseconds(200));
      ++records_sent_;
    } catch (const std::exception&) {
      // The daemon is not reading (not started, or gone): the record is lost, as on a wire.
    }
    next += period;
    const auto now = SteadyClock::now();
    if (next < now) next = now;
    while (!stop_telemetry_ && SteadyClock::now() < next) {
      std::this_thread::sleep_for(std::min<SteadyClock::duration>(next - SteadyClock::now(), std::chrono::milliseconds(10)));
    }
  }
}

void FakeController::write(const Bytes& bytes, std::chrono::milliseconds timeout) {
  std::lock_guard lock(write_mutex_);
  write_locked(bytes.data(), bytes.size(), timeout);
}

void FakeController::dribble(const Bytes& bytes, std::chrono::milliseconds pause) {
  for (const auto b : bytes) {
    {
      std::lock_guard lock(write_mutex_);
      write_locked(&b, 1, std::chrono::seconds(5));
    }
    std::this_thread::sleep_for(pause);
  }
}

void FakeController::write_locked(const std::uint8_t* data, std::size_t size, std::chrono::milliseconds timeout) {
  if (master_ < 0) throw std::runtime_error("fake controller: write while unplugged");
  const auto deadline = SteadyClock::now() + timeout;
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(master_, data + done, size - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      bytes_written_ += static_cast<std::uint64_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) fail("write");
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - SteadyClock::now());
    if (left.count() <= 0) {
      throw std::runtime_error("fake controller: the daemon did not read " + std::to_string(size - done) +
                               " bytes within " + std::to_string(timeout.count()) + " ms");
    }
    pollfd p{master_, POLLOUT, 0};
    ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 20)));
  }
}

void FakeController::reader_loop() {
  std::uint8_t buffer[4096];
  while (!stop_reader_) {
    pollfd p{master_, POLLIN, 0};
    const int polled = ::poll(&p, 1, 10);
    if (polled <= 0) continue;
    if ((p.revents & POLLIN) != 0) {
      const ssize_t n = ::read(master_, buffer, sizeof buffer);
      if (n > 0) {
        parse(buffer, static_cast<std::size_t>(n), SteadyClock::now());
        continue;
      }
    }
    // No slave open (cannot happen while the keeper is open) or an error: do not spin.
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
}

void FakeController::parse(const std::uint8_t* data, std::size_t size, SteadyClock::time_point time) {
  {
    std::lock_guard lock(mutex_);
    bytes_read_ += size;
    last_read_ = time;
    for (std::size_t i = 0; i < size; ++i) {
      const std::uint8_t b = data[i];
      if (filled_ == 0 && b != 0x7B) {
        stray_.push_back({b, time, plug_, commands_.size()});
        continue;
      }
      window_[filled_++] = b;
      if (filled_ < window_.size()) continue;
      filled_ = 0;
      CommandSeen seen;
      seen.bytes = window_;
      seen.time = time;
      seen.plug = plug_;
      seen.well_formed = window_[1] == 0 && window_[2] == 0 && window_[10] == 0x7D && xor_of(window_.data(), 9) == window_[9];
      seen.x = be16(&window_[3]);
      seen.y = be16(&window_[5]);
      seen.z = be16(&window_[7]);
      if (seen.well_formed) last_command_ = seen;
      commands_.push_back(seen);
    }
  }
  changed_.notify_all();
}

std::vector<CommandSeen> FakeController::commands() const {
  std::lock_guard lock(mutex_);
  return commands_;
}

std::size_t FakeController::command_count() const {
  std::lock_guard lock(mutex_);
  return commands_.size();
}

std::vector<StrayByte> FakeController::stray_bytes() const {
  std::lock_guard lock(mutex_);
  return stray_;
}

std::optional<CommandSeen> FakeController::wait_command(const std::function<bool(const CommandSeen&)>& predicate,
                                                        std::chrono::milliseconds timeout, std::size_t from,
                                                        std::size_t* index) {
  const auto deadline = SteadyClock::now() + timeout;
  std::unique_lock lock(mutex_);
  std::size_t next = from;
  for (;;) {
    for (; next < commands_.size(); ++next) {
      if (predicate(commands_[next])) {
        if (index != nullptr) *index = next;
        return commands_[next];
      }
    }
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout && next >= commands_.size()) return std::nullopt;
  }
}

bool FakeController::wait_command_count(std::size_t count, std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, timeout, [&] { return commands_.size() >= count; });
}

bool FakeController::wait_quiet(std::chrono::milliseconds quiet, std::chrono::milliseconds timeout) {
  const auto deadline = SteadyClock::now() + timeout;
  for (;;) {
    SteadyClock::time_point last;
    {
      std::lock_guard lock(mutex_);
      last = last_read_;
    }
    const auto now = SteadyClock::now();
    if (now - last >= quiet) return true;
    if (now >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

}  // namespace serial_tests
