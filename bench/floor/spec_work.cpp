#include "spec_work.hpp"

#include <sys/timerfd.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "wheeltec/asio_can/frame_io.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/telemetry/telemetry_json.hpp"

namespace wheeltec::bench {

SpecWork::SpecWork(int can, double rate_hz)  // 10.8 V: the spec's default telemetry.low_battery_v
    : can_(can), timer_(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC)), decoder_(10.8) {
  if (timer_ < 0 || !(rate_hz > 0)) throw std::runtime_error("spec work: no timerfd");
  const auto period_ns = static_cast<long>(std::lround(1e9 / rate_hz));
  itimerspec period{};
  period.it_interval.tv_sec = period_ns / 1'000'000'000;
  period.it_interval.tv_nsec = period_ns % 1'000'000'000;
  period.it_value = period.it_interval;
  ::timerfd_settime(timer_, 0, &period, nullptr);
}
SpecWork::~SpecWork() { ::close(timer_); }
void SpecWork::on_timer() {
  std::uint64_t expirations = 0;
  if (::read(timer_, &expirations, sizeof(expirations)) != static_cast<ssize_t>(sizeof(expirations))) return;
  const ControlCommand zero = quantize_command(Velocity{}, VelocityLimits{});
  const can_frame out = asio_can::to_socketcan(encode_control_frame(Dialect::manual, zero));
  if (::write(can_, &out, sizeof(out)) < 0) std::perror("CAN write");
}
bool SpecWork::on_frame(const can_frame& frame, RealtimeNanos time, std::string& batch) {
  const auto assembled = reassembler_.feed(asio_can::from_socketcan(frame), time);
  if (!assembled) return false;
  append_telemetry_notification(batch, decoder_.decode(assembled->bytes, assembled->time));
  return true;
}

}  // namespace wheeltec::bench
