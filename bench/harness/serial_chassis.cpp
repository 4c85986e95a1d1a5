#include "serial_chassis.hpp"

#include <chrono>
#include <exception>
#include <stdexcept>

#include <fmt/format.h>

#include "gateway_latency.hpp"  // bench_record()
#include "subscriber_set.hpp"   // api_call()

namespace bench {

RecordStream::RecordStream(PtyEndpoint& line, double hz) : line_(line), thread_([this, hz] { run(hz); }) {}

RecordStream::~RecordStream() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_requested_.notify_one();
  thread_.join();
}

std::optional<std::string> RecordStream::failure() const {
  std::lock_guard lock(mutex_);
  return failure_;
}

void RecordStream::run(double hz) {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / hz));
  auto next = std::chrono::steady_clock::now();
  for (int n = 0;; ++n) {
    try {
      line_.write(wheeltec::encode_record(bench_record(n)));
    } catch (const std::exception& error) {
      std::lock_guard lock(mutex_);
      failure_ = error.what();
      return;
    }
    next += period;
    std::unique_lock lock(mutex_);
    if (stop_requested_.wait_until(lock, next, [this] { return stopping_; })) return;
  }
}

void wait_until_ready(const std::filesystem::path& socket, ChildProgram& daemon, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  nlohmann::json status;
  do {
    status = api_call(socket, "status");
    if (status["bus"]["state"] == "up" && status["chassis"]["online"] == true && status["chassis"]["phase"] == "ready") {
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  } while (std::chrono::steady_clock::now() < deadline);
  throw std::runtime_error(fmt::format("the chassis did not become ready within {} s; last status {}\n{}",
                                       timeout_ms / 1000.0, status.dump(), daemon.log_tail()));
}

}  // namespace bench
