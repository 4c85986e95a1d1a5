#pragma once

// The recorder's MCAP channels (spec section 10, the table of topics): their topics, schema
// names and JSON Schema texts, and the two Foxglove messages made from each telemetry
// record. Pure: no I/O.
//
// Foxglove reads a JSON schema only for its members' types, and refuses a schema where a
// member's "type" is not one string (["number", "null"] included); so the members the
// daemon sends as null at times (status' battery_v before the first record, an event's
// client) are described by their other type, with the null case in their description.

#include <array>
#include <optional>
#include <string_view>

#include "message_time.hpp"

namespace wheeltec::record {

inline constexpr std::string_view kMessageEncoding = "json";
inline constexpr std::string_view kSchemaEncoding = "jsonschema";

enum class Channel { telemetry, status, events, odom, tf };

struct ChannelSpec {
  Channel channel;
  std::string_view topic;        // "/telemetry"
  std::string_view schema_name;  // "wheeltec.Telemetry"
  std::string_view schema;       // the JSON Schema document
};

// The five channels in the order of the spec's table, each with its own schema: a
// registry built by adding them in this order is the same in every file and chunk.
const std::array<ChannelSpec, 5>& channels();
const ChannelSpec& channel_spec(Channel channel);

inline constexpr std::string_view kOdomFrame = "odom";
inline constexpr std::string_view kBaseFrame = "base_footprint";

// /odom's foxglove.PoseInFrame for a telemetry record: frame `odom`, the record's odom x
// and y (z 0) and a quaternion of its yaw, stamped with its time. None when the record has
// no usable time or odom.
std::optional<Json> odom_pose_in_frame(const Json& record);
// /tf's foxglove.FrameTransform for a telemetry record: `odom` to `base_footprint`, the
// same pose.
std::optional<Json> odom_frame_transform(const Json& record);

}  // namespace wheeltec::record
