#include "recorder.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "options.hpp"

namespace wheeltec::record {
namespace {

constexpr std::chrono::milliseconds kTickPeriod{250};

RealtimeNanos now() { return std::chrono::time_point_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now()); }

}  // namespace

Recorder::Recorder(boost::asio::io_context& io, RecorderConfig config)
    : config_(std::move(config)),
      store_(config_.dir),
      black_box_(black_box_settings(config_), store_),
      subscription_(io.get_executor(), config_.socket),
      tick_timer_(io) {
  subscription_.on_telemetry([this](const client::Telemetry& record) { black_box_.on_telemetry(record.json, now()); });
  subscription_.on_status([this](const client::Status& status) { black_box_.on_status(status.json, now()); });
  subscription_.on_event([this](const client::Json& event) { black_box_.on_event(event, now()); });
  subscription_.on_up([this] { spdlog::info("recording from {}", config_.socket); });
  subscription_.on_down([this](const client::Subscription::Outage& outage) {
    if (outage.was_up) {
      spdlog::warn("wheeltecd lost ({}); retrying in {} ms", outage.error.message(), outage.retry_in.count());
      black_box_.on_daemon_lost(now());
    } else {
      spdlog::debug("wheeltecd not reachable ({}); retrying in {} ms", outage.error.message(), outage.retry_in.count());
    }
  });
}

void Recorder::start() {
  spdlog::info("keeping the last {} s in memory; files in {}", config_.before_s, config_.dir);
  subscription_.start();
  schedule_tick();
}

void Recorder::stop() {
  if (stopped_) return;
  stopped_ = true;
  tick_timer_.cancel();
  subscription_.stop();
  black_box_.finish(now());
}

void Recorder::schedule_tick() {
  tick_timer_.expires_after(kTickPeriod);
  tick_timer_.async_wait([this](const boost::system::error_code& error) {
    if (error || stopped_) return;
    black_box_.on_tick(now());
    schedule_tick();
  });
}

}  // namespace wheeltec::record
