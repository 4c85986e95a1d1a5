#pragma once

#include <nlohmann/json.hpp>

#include "wheeltec/telemetry_reassembler.hpp"

#include "api_counters.hpp"
#include "can_link.hpp"

namespace wheeltec::daemon {

// The `stats` result: flat counters, with discards and rejections keyed by reason.
nlohmann::json stats_to_json(const CanLinkCounters& link, const ReassemblyCounters& reassembly,
                             const ApiCounters& api, double uptime_s);

}  // namespace wheeltec::daemon
