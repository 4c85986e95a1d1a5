#include "wheeltec/control/chassis_phase.hpp"

#include <cmath>

namespace wheeltec {

std::string_view to_string(ChassisPhase phase) {
  switch (phase) {
    case ChassisPhase::booting: return "booting";
    case ChassisPhase::self_test: return "self-test";
    case ChassisPhase::ready: return "ready";
    case ChassisPhase::halted: return "halted";
  }
  return "unknown";
}

ChassisPhase phase_of(ChassisStage stage) {
  switch (stage) {
    case ChassisStage::booting: return ChassisPhase::booting;
    case ChassisStage::self_test_awaited:
    case ChassisStage::self_test_driving: return ChassisPhase::self_test;
    case ChassisStage::ready: return ChassisPhase::ready;
    case ChassisStage::halted: return ChassisPhase::halted;
  }
  return ChassisPhase::ready;
}

bool obeys_commands(ChassisPhase phase) { return phase == ChassisPhase::ready; }

bool shows_motion(const Velocity& measured) {
  using T = ChassisPhaseTracker;
  return std::abs(measured.vx) > T::kMotionSpeed || std::abs(measured.vy) > T::kMotionSpeed ||
         std::abs(measured.wz) > T::kMotionYawRate;
}

ChassisStage ChassisPhaseTracker::update(const PhaseInput& record) {
  const bool after_silence = !stage_ || !last_time_ || record.time - *last_time_ > kRebootGap;
  const bool flag_stop_changed = stage_ && record.stopped != (*stage_ == ChassisStage::booting ||
                                                               *stage_ == ChassisStage::halted);
  if (after_silence || flag_stop_changed) flag_stop_changed_ = record.time;
  last_time_ = record.time;
  stage_ = next_stage(record, after_silence);
  return *stage_;
}

ChassisStage ChassisPhaseTracker::next_stage(const PhaseInput& record, bool after_silence) const {
  if (after_silence) return record.stopped ? ChassisStage::booting : ChassisStage::ready;
  const std::chrono::nanoseconds since_change = record.time - flag_stop_changed_;
  switch (*stage_) {
    case ChassisStage::booting:
      if (!record.stopped) return shows_motion(record.measured) ? ChassisStage::self_test_driving
                                                                : ChassisStage::self_test_awaited;
      return since_change > kBootDelay + kBootTolerance ? ChassisStage::halted : ChassisStage::booting;
    case ChassisStage::self_test_awaited:
      if (record.stopped) return ChassisStage::halted;
      if (shows_motion(record.measured)) return ChassisStage::self_test_driving;
      return since_change >= kSelfTestWatch ? ChassisStage::ready : ChassisStage::self_test_awaited;
    case ChassisStage::self_test_driving:
      if (record.stopped) return ChassisStage::halted;
      return since_change >= kSelfTestLength ? ChassisStage::ready : ChassisStage::self_test_driving;
    case ChassisStage::halted:
      // A reset whose telemetry gap was too short to see is caught by its self-test drive.
      if (!record.stopped) return shows_motion(record.measured) ? ChassisStage::self_test_driving
                                                                : ChassisStage::self_test_awaited;
      return ChassisStage::halted;
    case ChassisStage::ready:
      return record.stopped ? ChassisStage::halted : ChassisStage::ready;
  }
  return ChassisStage::ready;
}

std::optional<ChassisPhase> ChassisPhaseTracker::phase() const {
  if (!stage_) return std::nullopt;
  return phase_of(*stage_);
}

void ChassisPhaseTracker::went_offline() {
  stage_.reset();
  last_time_.reset();
}

}  // namespace wheeltec
