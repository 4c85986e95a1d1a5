// The chassis rules on an arbitrary sequence of what the daemon can see: records (any time
// step, flag_stop, measured velocity, roll and pitch, non-finite ones included), drives from
// three clients, estop, release, the link going down and up, the deadman and the online
// timeout expiring, control periods, clients leaving, enable, disable,
// stop and a SIGHUP that changes the hazards' limits.
//
// Input: one byte picks the event (its low 4 bits), the bytes after it are its figures.
// Any crash or sanitizer report is a bug, and so is:
// - a frame that is not zero while the emergency stop is latched;
// - a drive accepted while latched;
// - a hazard found outside phase `ready`, while already latched, with source `client`, with
//   an empty reason, or without the supervisor's safety showing it afterwards;
// - `still_tilted` from release when the latch is not a tilt, or the latch gone after it;
// - anything still latched after a release that said `released`;
// - a send while the link is down, or a stop whose first send is not the zero frame;
// - the same sequence giving different frames or latches the second time (the rules are
//   pure: time comes in with each event).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "wheeltec/control/chassis_supervisor.hpp"

namespace {

using namespace std::chrono_literals;
using namespace wheeltec;

void check(bool ok) {
  if (!ok) std::abort();
}

class Input {
 public:
  explicit Input(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  bool empty() const { return at_ >= bytes_.size(); }
  std::uint8_t byte() { return empty() ? 0 : bytes_[at_++]; }
  std::int8_t signed_byte() { return static_cast<std::int8_t>(byte()); }
  // An angle in radians: -127..127 degrees, or NaN / infinity for 0x80 and the byte after it.
  double angle() {
    const std::int8_t value = signed_byte();
    if (value == std::numeric_limits<std::int8_t>::min()) {
      return byte() % 2 ? std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
    }
    return value * M_PI / 180.0;
  }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t at_ = 0;
};

// What one run saw, to compare two runs of the same input.
struct Trace {
  std::vector<ControlCommand> frames;
  std::vector<SafetyState> latches;
  friend bool operator==(const Trace&, const Trace&) = default;
};

Trace run(std::span<const std::uint8_t> bytes) {
  Input in(bytes);
  SupervisorSettings settings;
  ChassisSupervisor supervisor(settings);
  const RealtimeNanos epoch{std::chrono::seconds(1763800000)};
  MonotonicNanos now{1000s};
  const auto realtime = [&] { return epoch + (now - MonotonicNanos{1000s}); };
  Trace trace;

  // What the control loop does with the supervisor's answer; the link takes every frame.
  // Nothing goes out while the link is down, and a stop's zero frame goes before anything else.
  const auto carry_out = [&](const ControlActions& actions) {
    if (supervisor.link() == LinkState::down) check(actions.sends().empty());
    if (actions.deadman == DeadmanTimer::cancel && !actions.sends().empty()) {
      check(actions.sends().front() == LinkSend::command && supervisor.frame(now) == ControlCommand{});
    }
    for (const LinkSend what : actions.sends()) {
      if (what != LinkSend::command) continue;
      const ControlCommand frame = supervisor.frame(now);
      if (supervisor.safety()) check(frame == ControlCommand{});
      supervisor.frame_sent(frame, now);
      trace.frames.push_back(frame);
    }
  };

  const auto check_frame = [&] {
    const ControlCommand frame = supervisor.frame(now);
    if (supervisor.safety()) check(frame == ControlCommand{});
    trace.frames.push_back(frame);
  };

  while (!in.empty()) {
    const std::uint8_t op = in.byte();
    switch (op & 0x0f) {
      case 0: {  // a record, 0-255 ms after the previous event
        now += std::chrono::milliseconds(in.byte());
        const std::uint8_t flags = in.byte();
        Velocity measured{in.signed_byte() * 0.01, in.signed_byte() * 0.01, in.signed_byte() * 0.02};
        if (flags & 0x02) measured.vx = std::numeric_limits<double>::quiet_NaN();
        RecordInput record{PhaseInput{realtime(), (flags & 0x01) != 0, measured}, in.angle(), in.angle()};
        const bool latched_before = supervisor.safety().has_value();
        const RecordOutcome outcome = supervisor.record(record, now);
        if (const auto& hazard = outcome.actions.latched) {
          check(!latched_before);
          check(supervisor.phase() == ChassisPhase::ready);
          check(hazard->source != LatchSource::client);
          check(!hazard->reason.empty());
          check(!hazard->by);
          check(supervisor.safety() == hazard);
        }
        carry_out(outcome.actions);
        break;
      }
      case 1: {  // a drive from client 1-3
        const ClientId client = 1 + in.byte() % 3;
        const Velocity target{in.signed_byte() * 0.01, in.signed_byte() * 0.01, in.signed_byte() * 0.03};
        const bool latched = supervisor.safety().has_value();
        const DriveDecision decision = supervisor.drive(client, target, now);
        if (latched) check(decision.refusal == DriveRefusal::estop_latched);
        carry_out(decision.actions);
        break;
      }
      case 2: {
        const ControlActions actions = supervisor.estop(Latch{LatchSource::client, "fuzz", realtime(), ClientId{1}});
        if (actions.latched) check(supervisor.safety() == actions.latched);
        carry_out(actions);
        break;
      }
      case 3: {
        const SafetyState before = supervisor.safety();
        const ReleaseDecision decision = supervisor.release(ClientId{2});
        check(decision.actions.released.has_value() == (decision.outcome == ReleaseOutcome::released));
        switch (decision.outcome) {
          case ReleaseOutcome::released: check(before && !supervisor.safety().has_value()); break;
          case ReleaseOutcome::not_latched: check(!before); break;
          case ReleaseOutcome::still_tilted:
            check(before && before->source == LatchSource::tilt && supervisor.safety() == before);
            break;
        }
        break;
      }
      case 4: carry_out(supervisor.link_changed(in.byte() % 2 ? LinkState::up : LinkState::down)); break;
      case 5:  // time passes: the deadman and the online timeout
        now += std::chrono::milliseconds(in.byte() * 10);
        carry_out(supervisor.expire_deadman(now));
        supervisor.expire_online(now);
        break;
      case 6:  // a control period
        carry_out(supervisor.period(now));
        break;
      case 7: carry_out(supervisor.client_gone(1 + in.byte() % 3)); break;
      case 8: carry_out(supervisor.start()); break;
      case 9: carry_out(supervisor.enable(in.byte() % 2 ? EnableRequest::client : EnableRequest::at_start).actions); break;
      case 10: carry_out(supervisor.disable()); break;
      case 11: carry_out(supervisor.stop()); break;
      case 12: {  // SIGHUP: new hazard limits (within the config's ranges or just outside)
        const std::uint8_t enabled = in.byte();
        settings.hazards.collision = {(enabled & 1) != 0, 0.05 + in.byte() * 0.01};
        settings.hazards.tilt = {(enabled & 2) != 0, 10.0 + in.byte() % 80, 0.05 + in.byte() * 0.02};
        settings.hazards.stall = {(enabled & 4) != 0, 0.2 + in.byte() * 0.04};
        carry_out(supervisor.apply(settings));
        break;
      }
      case 13: carry_out(supervisor.shut_down()); break;
      default: break;
    }
    check_frame();
    trace.latches.push_back(supervisor.safety());
  }
  return trace;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  check(run(bytes) == run(bytes));
  return 0;
}
