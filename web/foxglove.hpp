#pragma once

// The Foxglove WebSocket protocol (subprotocol foxglove.websocket.v1) as wheeltec-web
// speaks it: the server's JSON messages, the binary message-data frame, and the parsing
// of what clients send. Pure: no I/O. docs/web.md lists the channels.

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "wheeltec/client/records.hpp"

namespace wheeltec::web::foxglove {

using client::Json;

inline constexpr std::string_view kSubprotocol = "foxglove.websocket.v1";
inline constexpr std::string_view kCmdVelTopic = "/wheeltec/cmd_vel";
// The emergency stop's client-publish topics (spec section 12): `estop` with the payload's
// reason (anyone), `release` (with the token); the payload of a release is not read.
inline constexpr std::string_view kEstopTopic = "/wheeltec/estop";
inline constexpr std::string_view kReleaseTopic = "/wheeltec/release";

// Whether a client may advertise `topic` to publish on it.
bool client_publish_topic(std::string_view topic);

enum class ChannelId : std::uint32_t { telemetry = 1, status = 2, odom = 3, imu = 4 };

struct Channel {
  ChannelId id;
  std::string topic;
  std::string schema_name;
  std::string schema;  // JSON schema, as text
};

// The four server channels, in id order.
const std::vector<Channel>& channels();

enum class Level { info = 0, warning = 1, error = 2 };

// metadata: string values only, as the protocol wants them.
std::string server_info(std::string_view session_id, const std::map<std::string, std::string>& metadata = {});
std::string advertise();
std::string status(Level level, std::string_view message, std::string_view id = {});

// Opcode 0x01, subscription id (uint32 LE), timestamp (uint64 LE, ns), payload.
std::string message_data(std::uint32_t subscription_id, std::uint64_t timestamp_ns, std::string_view payload);

// What a client may send as text.
struct Subscribe {
  struct Entry {
    std::uint32_t subscription_id;
    std::uint32_t channel_id;
  };
  std::vector<Entry> subscriptions;
};
struct Unsubscribe {
  std::vector<std::uint32_t> subscription_ids;
};
struct ClientAdvertise {
  struct Entry {
    std::uint32_t id;
    std::string topic;
    std::string encoding;
  };
  std::vector<Entry> channels;
};
struct ClientUnadvertise {
  std::vector<std::uint32_t> channel_ids;
};
struct ProtocolError {
  std::string message;
};
using ClientMessage = std::variant<Subscribe, Unsubscribe, ClientAdvertise, ClientUnadvertise, ProtocolError>;

ClientMessage parse_text(std::string_view text);

// Client publish: opcode 0x01, the client's channel id (uint32 LE), payload.
struct ClientPublish {
  std::uint32_t channel_id;
  std::string_view payload;
};
std::variant<ClientPublish, ProtocolError> parse_binary(std::string_view data);

// /wheeltec/cmd_vel's payload, {"vx":..,"vy":..,"wz":..} (absent = 0): the params of a
// `drive`, or what is wrong with it.
std::variant<client::Velocity, ProtocolError> parse_cmd_vel(std::string_view payload);

// The telemetry record as the odom channel's foxglove.PoseInFrame and the imu channel's
// message; nanoseconds since the epoch of its `time`.
Json odom_pose(const client::Telemetry& record);
Json imu(const client::Telemetry& record);
std::uint64_t timestamp_ns(double seconds);

}  // namespace wheeltec::web::foxglove
