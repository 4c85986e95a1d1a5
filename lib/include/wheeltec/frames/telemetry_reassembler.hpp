#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include "wheeltec/frames/can_frame.hpp"
#include "wheeltec/frames/telemetry_record.hpp"
#include "wheeltec/clocks.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

inline constexpr std::uint32_t kTelemetryId1 = 0x101;
inline constexpr std::uint32_t kTelemetryId2 = 0x102;
inline constexpr std::uint32_t kTelemetryId3 = 0x103;

// Why a (partial) group was thrown away before it could form a record.
enum class DiscardReason : std::size_t {
  missing_frame,   // a frame of the group never came (e.g. 0x101 then 0x101 again after 0x102, or 0x102 with no 0x101)
  repeated_frame,  // the same ID twice in a row
  out_of_order,    // 0x103 where 0x102 was due
  wrong_dlc,       // a telemetry ID with DLC other than 8
  extended_id,     // a telemetry ID sent as a 29-bit frame
  rtr,             // a remote request on a telemetry ID
  gap,             // more than max_gap between two frames of one group
};
inline constexpr std::size_t kDiscardReasonCount = 7;

// Why a complete 24-byte group was not accepted as a record.
enum class RejectReason : std::size_t { bad_header, bad_tail, bad_checksum };
inline constexpr std::size_t kRejectReasonCount = 3;

std::string_view to_string(DiscardReason reason);  // "missing_frame", ...
std::string_view to_string(RejectReason reason);   // "bad_header", ...

struct ReassemblyCounters {
  std::uint64_t frames = 0;           // frames fed that carry a telemetry ID (any format)
  std::uint64_t accepted = 0;         // records returned
  std::uint64_t resync_skipped = 0;   // 0x102/0x103 frames dropped while waiting for the next 0x101
  std::array<std::uint64_t, kDiscardReasonCount> discarded{};
  std::array<std::uint64_t, kRejectReasonCount> rejected{};
};

struct AssembledRecord {
  RecordBytes bytes;
  RealtimeNanos time;  // receive time of the closing 0x103 frame
};

// Rebuilds 24-byte telemetry records from 0x101, 0x102, 0x103 frames (in that order,
// standard IDs, DLC 8, not RTR, at most max_gap apart). A broken group is counted once,
// under the first fault seen; later frames of it are skipped until the next 0x101.
// Frames with other IDs and error frames are ignored and not counted.
// Never allocates.
class TelemetryReassembler {
 public:
  explicit TelemetryReassembler(std::chrono::nanoseconds max_gap = std::chrono::milliseconds(20));

  // `time` is the frame's receive time. Returns a record when this frame completes
  // a group that passes check_record().
  std::optional<AssembledRecord> feed(const CanFrame& frame, RealtimeNanos time);

  // Forgets any partial group without counting it (e.g. the link went down).
  void reset();

  const ReassemblyCounters& counters() const { return counters_; }

 private:
  // The first three are also the slot of the frame due next.
  enum class Stage { idle = 0, have_first = 1, have_second = 2, resync = 3 };

  std::optional<AssembledRecord> feed_out_of_course(const CanFrame& frame, RealtimeNanos time);

  std::chrono::nanoseconds max_gap_;
  Stage stage_ = Stage::idle;
  RealtimeNanos last_time_{};
  RecordBytes bytes_{};
  ReassemblyCounters counters_;
};

}  // namespace wheeltec
