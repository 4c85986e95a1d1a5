#pragma once

// The relay floor's --spec-work: the spec's own work for each record and control period, done
// with wheeltecd's pure code (lib/) and nothing around it: the record's real notification and a
// control frame every 1/rate_hz, where the relay writes a fixed line and sends no control frames.
#include <linux/can.h>

#include <string>

#include "wheeltec/clocks.hpp"
#include "wheeltec/telemetry/telemetry_decoder.hpp"
#include "wheeltec/frames/telemetry_reassembler.hpp"

namespace wheeltec::bench {

class SpecWork {
 public:
  SpecWork(int can, double rate_hz);  // `can`: the relay's raw CAN socket
  ~SpecWork();
  SpecWork(const SpecWork&) = delete;
  SpecWork& operator=(const SpecWork&) = delete;
  int timer_fd() const { return timer_; }
  void on_timer();  // the timer fired: one zero-velocity control frame (nobody drives at idle), as wheeltecd's tick
  // Reassembly, checks, decoding, odometry, attitude; a record's notification appended to `batch` (true).
  bool on_frame(const can_frame& frame, RealtimeNanos time, std::string& batch);
 private:
  int can_, timer_;
  TelemetryReassembler reassembler_;
  TelemetryDecoder decoder_;
};

}  // namespace wheeltec::bench
