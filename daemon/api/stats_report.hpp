#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

#include "api_counters.hpp"
#include "link/chassis_link.hpp"

namespace wheeltec::daemon {

// The `stats` result: the link's counters (with discards and rejections keyed by reason),
// the records accepted and the API's counters.
nlohmann::json stats_to_json(const ChassisLink& link, std::uint64_t records_accepted, const ApiCounters& api,
                             double uptime_s);

}  // namespace wheeltec::daemon
