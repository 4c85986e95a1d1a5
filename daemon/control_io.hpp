#pragma once

#include <cstdint>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "can_link.hpp"
#include "control_ports.hpp"
#include "periodic_timer.hpp"
#include "stall_sentinel.hpp"

namespace wheeltec::daemon {

// The daemon's ControlPorts: the steady clock, the CAN link, a timerfd tick, two Asio
// timers and the stall sentinel, retimed when the control rate changes.
class ControlIo {
 public:
  ControlIo(boost::asio::io_context& io, CanLink& link, double rate_hz);

  ControlPorts ports() {
    return {clock_, bus_, period_timer_, enable_timer_, deadman_timer_, stall_guard_};
  }

 private:
  class SteadyClock : public MonotonicClock {
   public:
    MonotonicNanos now() const override { return std::chrono::steady_clock::now(); }
  };

  class LinkSink : public FrameSink {
   public:
    explicit LinkSink(CanLink& link) : link_(link) {}
    bool bus_down() const override { return link_.state() == BusState::down; }
    bool send(const CanFrame& frame) override { return link_.send(frame); }

   private:
    CanLink& link_;
  };

  class AsioTimer : public OneShotTimer {
   public:
    explicit AsioTimer(boost::asio::io_context& io) : timer_(io) {}
    void wait_until(MonotonicNanos expiry, Handler handler) override;
    void cancel() override;

   private:
    boost::asio::steady_timer timer_;
    // A completion already queued when the wait was replaced or cancelled is not aborted
    // by Asio: it is told apart by its generation.
    std::uint64_t generation_ = 0;
  };

  class SentinelGuard : public StallGuard {
   public:
    SentinelGuard(const std::string& interface, double rate_hz)
        : sentinel_(interface, StallSentinel::timing_for_rate(rate_hz)) {}
    void start() override { sentinel_.start(); }
    void beat(std::uint32_t zero_frame_id) override { sentinel_.beat(zero_frame_id); }
    void disarm() override { sentinel_.disarm(); }
    void set_rate(double rate_hz) override { sentinel_.retime(StallSentinel::timing_for_rate(rate_hz)); }

   private:
    StallSentinel sentinel_;
  };

  SteadyClock clock_;
  LinkSink bus_;
  PeriodicTimer period_timer_;
  AsioTimer enable_timer_;
  AsioTimer deadman_timer_;
  SentinelGuard stall_guard_;
};

}  // namespace wheeltec::daemon
