#pragma once

#include <cstdint>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include "wheeltec/config/config.hpp"

#include "link/chassis_link.hpp"
#include "control_ports.hpp"
#include "periodic_timer.hpp"
#include "safety_state_file.hpp"
#include "stall_sentinel.hpp"

namespace wheeltec::daemon {

// The daemon's ControlPorts: the steady clock, the chassis link, a timerfd tick, three Asio
// timers, the stall sentinel (retimed when the control rate changes) and the latch's state file.
class ControlIo {
 public:
  ControlIo(boost::asio::io_context& io, ChassisLink& link, const GatewayConfig& config);

  ControlPorts ports() {
    return {clock_, link_, period_timer_, enable_timer_, deadman_timer_, offline_timer_, stall_guard_, latch_file_};
  }
  const SafetyStateFile& latch_file() const { return latch_file_; }
  // The link's descriptor for the sentinel (-1: closed).
  void use_port(int fd) { stall_guard_.use_port(fd); }

 private:
  class SteadyClock : public MonotonicClock {
   public:
    MonotonicNanos now() const override { return std::chrono::steady_clock::now(); }
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
    // The sentinel is forked here, before the Gateway's API socket and any client's
    // connection exist. Forked later, it would hold copies of them until it has closed
    // its files, and a daemon killed in that time would leave its socket accepting
    // connections that nobody answers, and its restart finding the socket in use.
    SentinelGuard(StallSentinel::ZeroFrame zero, double rate_hz)
        : sentinel_(std::move(zero), StallSentinel::timing_for_rate(rate_hz)) {
      sentinel_.start();
    }
    void beat() override { sentinel_.beat(); }
    void disarm() override { sentinel_.disarm(); }
    void set_rate(double rate_hz) override { sentinel_.retime(StallSentinel::timing_for_rate(rate_hz)); }
    void use_port(int fd) { sentinel_.use_port(fd); }

   private:
    StallSentinel sentinel_;
  };

  SteadyClock clock_;
  ChassisLink& link_;
  PeriodicTimer period_timer_;
  AsioTimer enable_timer_;
  AsioTimer deadman_timer_;
  AsioTimer offline_timer_;
  SentinelGuard stall_guard_;
  SafetyStateFile latch_file_;
};

}  // namespace wheeltec::daemon
