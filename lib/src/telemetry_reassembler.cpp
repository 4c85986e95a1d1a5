#include "wheeltec/telemetry_reassembler.hpp"

#include <algorithm>

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

bool is_telemetry_id(std::uint32_t id) {
  return id == kTelemetryId1 || id == kTelemetryId2 || id == kTelemetryId3;
}

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

TelemetryReassembler::TelemetryReassembler(Nanos max_gap) : max_gap_(max_gap) {}

void TelemetryReassembler::reset() { stage_ = Stage::idle; }

std::optional<AssembledRecord> TelemetryReassembler::feed(const CanFrame& frame, Nanos time) {
  if (frame.error || !is_telemetry_id(frame.id)) return std::nullopt;
  ++counters_.frames;

  const auto discard = [this](DiscardReason reason) {
    ++counters_.discarded[static_cast<std::size_t>(reason)];
    stage_ = Stage::resync;
  };
  const auto store = [&](std::size_t slot, Stage next) {
    std::copy_n(frame.data.begin(), kFrameBytes, bytes_.begin() + slot * kFrameBytes);
    last_time_ = time;
    stage_ = next;
  };
  // A clock stepping backwards yields a negative interval, which is not a gap.
  const auto too_late = [&] { return time - last_time_ > max_gap_; };

  if (const auto fault = format_fault(frame)) {
    // In resync the broken group was already counted, unless this would have started a new one.
    if (stage_ == Stage::resync && frame.id != kTelemetryId1) {
      ++counters_.resync_skipped;
    } else {
      discard(*fault);
    }
    return std::nullopt;
  }

  switch (frame.id) {
    case kTelemetryId1:
      if (stage_ == Stage::have_first) discard(DiscardReason::repeated_frame);
      if (stage_ == Stage::have_second) discard(DiscardReason::missing_frame);
      store(0, Stage::have_first);
      return std::nullopt;

    case kTelemetryId2:
      switch (stage_) {
        case Stage::have_first:
          if (too_late()) {
            discard(DiscardReason::gap);
          } else {
            store(1, Stage::have_second);
          }
          break;
        case Stage::idle: discard(DiscardReason::missing_frame); break;
        case Stage::have_second: discard(DiscardReason::repeated_frame); break;
        case Stage::resync: ++counters_.resync_skipped; break;
      }
      return std::nullopt;

    default:  // kTelemetryId3
      switch (stage_) {
        case Stage::have_second:
          if (too_late()) {
            discard(DiscardReason::gap);
            return std::nullopt;
          }
          store(2, Stage::idle);
          if (const auto reason = reject_reason(check_record(bytes_))) {
            ++counters_.rejected[static_cast<std::size_t>(*reason)];
            return std::nullopt;
          }
          ++counters_.accepted;
          return AssembledRecord{bytes_, time};
        case Stage::have_first: discard(DiscardReason::out_of_order); break;
        case Stage::idle: discard(DiscardReason::missing_frame); break;
        case Stage::resync: ++counters_.resync_skipped; break;
      }
      return std::nullopt;
  }
}

}  // namespace wheeltec
