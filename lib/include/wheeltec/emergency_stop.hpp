#pragma once

// The latched emergency stop (spec section 12): who or what latched it, why and when, the
// one JSON shape of it (status `safety`, the -32007 error's data), and the state file that
// keeps it across restarts, as text. Pure: the daemon writes and reads the file.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include <nlohmann/json_fwd.hpp>

#include "wheeltec/clocks.hpp"
#include "wheeltec/control_arbiter.hpp"
#include "wheeltec/types.hpp"

namespace wheeltec {

enum class LatchSource { client, collision, tilt, stall };

inline constexpr std::array<EnumName<LatchSource>, 4> kLatchSourceNames{{
    {LatchSource::client, "client"},
    {LatchSource::collision, "collision"},
    {LatchSource::tilt, "tilt"},
    {LatchSource::stall, "stall"},
}};
constexpr std::span<const EnumName<LatchSource>> name_table(LatchSource) { return kLatchSourceNames; }
std::string_view to_string(LatchSource source);

struct Latch {
  LatchSource source = LatchSource::client;
  std::string reason;          // the caller's text ("" when none), or a hazard's figures
  RealtimeNanos since{};
  std::optional<ClientId> by;  // the caller, for source client
  friend bool operator==(const Latch&, const Latch&) = default;
};

// Empty: not latched.
using SafetyState = std::optional<Latch>;

// {"latched", "source", "reason", "since", "by"}.
nlohmann::json safety_to_json(const SafetyState& state);

// The state file's text (one JSON object and a newline).
std::string encode_safety_file(const SafetyState& state);

// What a state file says. A file that is not one this encoder wrote is an error, with
// what is wrong; the daemon then starts latched (fail safe).
std::variant<SafetyState, std::string> decode_safety_file(std::string_view text);

// The latch a damaged state file leaves: source client, a reason that says so.
Latch damaged_file_latch(std::string_view problem, RealtimeNanos now);

}  // namespace wheeltec
