#include "wheeltec/frames/telemetry_reassembler.hpp"

#include <cstring>

namespace wheeltec {

std::string_view to_string(DiscardReason reason) {
  switch (reason) {
    case DiscardReason::missing_frame: return "missing_frame";
    case DiscardReason::repeated_frame: return "repeated_frame";
    case DiscardReason::out_of_order: return "out_of_order";
    case DiscardReason::wrong_dlc: return "wrong_dlc";
    case DiscardReason::extended_id: return "extended_id";
    case DiscardReason::rtr: return "rtr";
    case DiscardReason::gap: return "gap";
  }
  return "unknown";
}

std::string_view to_string(RejectReason reason) {
  switch (reason) {
    case RejectReason::bad_header: return "bad_header";
    case RejectReason::bad_tail: return "bad_tail";
    case RejectReason::bad_checksum: return "bad_checksum";
  }
  return "unknown";
}

namespace {

constexpr std::size_t kFrameBytes = 8;

// 0x101..0x103 as slot 0..2 of the record; anything else as a larger number.
std::uint32_t slot_of(std::uint32_t id) { return id - kTelemetryId1; }

// The first format fault, checked in this order; the frame is a standard data frame with
// DLC 8 when none.
std::optional<DiscardReason> format_fault(const CanFrame& frame) {
  if (frame.extended) return DiscardReason::extended_id;
  if (frame.rtr) return DiscardReason::rtr;
  if (frame.dlc != kFrameBytes) return DiscardReason::wrong_dlc;
  return std::nullopt;
}

std::optional<RejectReason> reject_reason(RecordFault fault) {
  switch (fault) {
    case RecordFault::none: return std::nullopt;
    case RecordFault::bad_header: return RejectReason::bad_header;
    case RecordFault::bad_tail: return RejectReason::bad_tail;
    case RecordFault::bad_checksum: return RejectReason::bad_checksum;
  }
  return std::nullopt;
}

}  // namespace

TelemetryReassembler::TelemetryReassembler(std::chrono::nanoseconds max_gap) : max_gap_(max_gap) {}

void TelemetryReassembler::reset() { stage_ = Stage::idle; }

std::optional<AssembledRecord> TelemetryReassembler::feed(const CanFrame& frame, RealtimeNanos time) {
  const std::uint32_t slot = slot_of(frame.id);
  if (frame.error || slot > 2) return std::nullopt;
  ++counters_.frames;

  // The usual case first: a well-formed frame that is the next of its group, in time (the
  // first frame of a group has no gap to keep). Flags and DLC are tested together, without
  // a branch each; any fault takes the full path below, which tells the faults apart.
  // A clock stepping backwards yields a negative interval, which is not a gap.
  const bool well_formed = !frame.extended & !frame.rtr & (frame.dlc == kFrameBytes);
  if (well_formed && slot == static_cast<std::uint32_t>(stage_) && (slot == 0 || time - last_time_ <= max_gap_)) {
    std::memcpy(bytes_.data() + slot * kFrameBytes, frame.data.data(), kFrameBytes);
    last_time_ = time;
    if (slot < 2) {
      stage_ = static_cast<Stage>(slot + 1);
      return std::nullopt;
    }
    stage_ = Stage::idle;
    if (const RecordFault fault = check_record(bytes_); fault != RecordFault::none) [[unlikely]] {
      ++counters_.rejected[static_cast<std::size_t>(*reject_reason(fault))];
      return std::nullopt;
    }
    ++counters_.accepted;
    return AssembledRecord{bytes_, time};
  }
  return feed_out_of_course(frame, time);
}

// Faulty frames and frames that do not continue the group, with the accounting of why.
std::optional<AssembledRecord> TelemetryReassembler::feed_out_of_course(const CanFrame& frame, RealtimeNanos time) {
  const auto discard = [this](DiscardReason reason) {
    ++counters_.discarded[static_cast<std::size_t>(reason)];
    stage_ = Stage::resync;
  };
  const auto store = [&](std::size_t slot, Stage next) {
    std::memcpy(bytes_.data() + slot * kFrameBytes, frame.data.data(), kFrameBytes);
    last_time_ = time;
    stage_ = next;
  };

  if (const auto fault = format_fault(frame)) {
    // In resync the broken group was already counted, unless this would have started a new one.
    if (stage_ == Stage::resync && frame.id != kTelemetryId1) {
      ++counters_.resync_skipped;
    } else {
      discard(*fault);
    }
    return std::nullopt;
  }

  // Well-formed, but not the frame the group needed next (or too late for it).
  switch (frame.id) {
    case kTelemetryId1:
      if (stage_ == Stage::have_first) discard(DiscardReason::repeated_frame);
      if (stage_ == Stage::have_second) discard(DiscardReason::missing_frame);
      store(0, Stage::have_first);
      return std::nullopt;

    case kTelemetryId2:
      switch (stage_) {
        case Stage::have_first: discard(DiscardReason::gap); break;
        case Stage::idle: discard(DiscardReason::missing_frame); break;
        case Stage::have_second: discard(DiscardReason::repeated_frame); break;
        case Stage::resync: ++counters_.resync_skipped; break;
      }
      return std::nullopt;

    default:  // kTelemetryId3
      switch (stage_) {
        case Stage::have_second: discard(DiscardReason::gap); break;
        case Stage::have_first: discard(DiscardReason::out_of_order); break;
        case Stage::idle: discard(DiscardReason::missing_frame); break;
        case Stage::resync: ++counters_.resync_skipped; break;
      }
      return std::nullopt;
  }
}

}  // namespace wheeltec
