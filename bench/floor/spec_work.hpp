#pragma once

// The relay floor's --spec-work: the work the spec asks of a gateway for each record and
// each control period, done with wheeltecd's own pure code (lib/) and nothing around it.
// It tells the daemon's design apart from the spec's own cost: the relay floor writes a
// fixed line per 0x103 and sends no control frames; this writes the record's real
// notification and a control frame every 1/rate_hz, as wheeltecd must.

#include <linux/can.h>

#include <cstdint>
#include <string>

#include "wheeltec/clocks.hpp"
#include "wheeltec/telemetry_decoder.hpp"
#include "wheeltec/telemetry_reassembler.hpp"

namespace wheeltec::bench {

class SpecWork {
 public:
  // `can` is the relay's raw CAN socket; the control period is 1/`rate_hz`.
  SpecWork(int can, double rate_hz);
  ~SpecWork();
  SpecWork(const SpecWork&) = delete;
  SpecWork& operator=(const SpecWork&) = delete;

  // The timerfd to wait on with the relay's sockets.
  int timer_fd() const { return timer_; }

  // The timer fired: reads its expirations and sends one zero-velocity control frame
  // (nobody drives at idle), as wheeltecd's control tick does.
  void on_timer();

  // A frame read from the CAN socket with its kernel receive time: reassembly, checks,
  // decoding, odometry and attitude; a completed record's notification is appended to
  // `batch`. Returns whether a record was completed.
  bool on_frame(const can_frame& frame, RealtimeNanos time, std::string& batch);

 private:
  int can_;
  int timer_;
  TelemetryReassembler reassembler_;
  TelemetryDecoder decoder_;
};

}  // namespace wheeltec::bench
