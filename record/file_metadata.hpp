#pragma once

// The metadata record `wheeltec` of an incident file (spec section 10): which daemon,
// link and chassis it was recorded from, and the triggers it holds. Pure: no I/O.

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "message_time.hpp"
#include "triggers.hpp"

namespace wheeltec::record {

inline constexpr std::string_view kMetadataName = "wheeltec";

// [{"trigger":"deadman","time":1795552460.482002},...]: the times in seconds since the
// epoch with 6 decimals, as the daemon writes its own.
std::string triggers_json(const std::vector<FiredTrigger>& triggers);

// {version, transport, device, chassis, triggers} from the latest status object (its
// version, bus.transport, bus.interface and chassis.type; "" for each it lacks, or when no
// status came at all: pass null) and the file's triggers. As MCAP's Map<string, string>
// (wheeltec::mcap::Metadata).
std::map<std::string, std::string> file_metadata(const Json& status, const std::vector<FiredTrigger>& triggers);

}  // namespace wheeltec::record
