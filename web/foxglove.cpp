#include "foxglove.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "wheeltec/drive_velocity.hpp"
#include "wheeltec/config/json_text.hpp"

namespace wheeltec::web::foxglove {
namespace {

// A client's JSON text, read as the daemon reads its requests.
std::variant<Json, ProtocolError> read_json(std::string_view text, std::string_view what) {
  json_text::StrictRead read = json_text::read_strict(text, json_text::kMaxMessageDepth);
  if (!read.refusal) return std::move(read.document);
  if (read.refusal->reason == json_text::Refusal::Reason::not_json) {
    return ProtocolError{fmt::format("{}not JSON: {}", what, read.refusal->message)};
  }
  return ProtocolError{fmt::format("{}{}", what, read.refusal->message)};
}

Json number_object(std::initializer_list<const char*> keys) {
  Json properties = Json::object();
  Json required = Json::array();
  for (const char* key : keys) {
    properties[key] = {{"type", "number"}};
    required.push_back(key);
  }
  return {{"type", "object"}, {"properties", properties}, {"required", required}};
}

Json time_schema() {
  return {{"type", "object"},
          {"properties", {{"sec", {{"type", "integer"}}}, {"nsec", {{"type", "integer"}}}}},
          {"required", {"sec", "nsec"}}};
}

std::string telemetry_schema() {
  Json schema = {{"title", "wheeltec.Telemetry"},
                 {"type", "object"},
                 {"properties",
                  {{"seq", {{"type", "integer"}}},
                   {"time", {{"type", "number"}}},
                   {"stopped", {{"type", "boolean"}}},
                   {"velocity", number_object({"vx", "vy", "wz"})},
                   {"accel", number_object({"x", "y", "z"})},
                   {"gyro", number_object({"x", "y", "z"})},
                   {"battery",
                    {{"type", "object"},
                     {"properties", {{"voltage", {{"type", "number"}}}, {"low", {{"type", "boolean"}}}}}}},
                   {"odom", number_object({"x", "y", "yaw"})},
                   {"orientation", number_object({"w", "x", "y", "z", "roll", "pitch", "yaw"})}}},
                 {"required", {"seq", "time", "velocity", "accel", "gyro", "battery", "odom"}}};
  return schema.dump();
}

std::string status_schema() {
  Json schema = {{"title", "wheeltec.Status"},
                 {"type", "object"},
                 {"properties",
                  {{"version", {{"type", "string"}}},
                   {"uptime_s", {{"type", "number"}}},
                   {"bus", {{"type", "object"}}},
                   {"chassis", {{"type", "object"}}},
                   {"dock", {{"type", "object"}}},
                   {"control", {{"type", "object"}}},
                   {"safety", {{"type", "object"}}}}}};
  return schema.dump();
}

std::string pose_schema() {
  Json schema = {{"title", "foxglove.PoseInFrame"},
                 {"type", "object"},
                 {"properties",
                  {{"timestamp", time_schema()},
                   {"frame_id", {{"type", "string"}}},
                   {"pose",
                    {{"type", "object"},
                     {"properties",
                      {{"position", number_object({"x", "y", "z"})},
                       {"orientation", number_object({"x", "y", "z", "w"})}}}}}}}};
  return schema.dump();
}

std::string imu_schema() {
  Json schema = {{"title", "wheeltec.Imu"},
                 {"type", "object"},
                 {"properties",
                  {{"timestamp", time_schema()},
                   {"frame_id", {{"type", "string"}}},
                   {"orientation", number_object({"x", "y", "z", "w"})},
                   {"angular_velocity", number_object({"x", "y", "z"})},
                   {"linear_acceleration", number_object({"x", "y", "z"})}}}};
  return schema.dump();
}

void put_le(std::string& out, std::uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((value >> (8 * i)) & 0xFF));
}

std::uint32_t get_le32(std::string_view data, std::size_t at) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = (value << 8) | static_cast<unsigned char>(data[at + i]);
  return value;
}

std::uint32_t id_of(const Json& value, const char* what) {
  if (!value.is_number_unsigned() || value.get<std::uint64_t>() > std::numeric_limits<std::uint32_t>::max()) {
    throw std::invalid_argument(fmt::format("{} must be an integer in [0, 4294967295]", what));
  }
  return value.get<std::uint32_t>();
}

const Json& member(const Json& object, const char* key, bool (Json::*is)() const noexcept, const char* type) {
  const auto found = object.find(key);
  if (found == object.end() || !((*found).*is)()) throw std::invalid_argument(fmt::format("\"{}\" must be {}", key, type));
  return *found;
}

Json time_of(const client::Telemetry& record) {
  const std::uint64_t ns = timestamp_ns(record.time);
  return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}};
}

ClientMessage parse_object(const Json& message) {
  if (!message.is_object()) return ProtocolError{"expected a JSON object"};
  const auto op = message.find("op");
  if (op == message.end() || !op->is_string()) return ProtocolError{"missing \"op\""};
  const std::string name = op->get<std::string>();
  if (name == "subscribe") {
    Subscribe result;
    for (const Json& entry : member(message, "subscriptions", &Json::is_array, "an array")) {
      if (!entry.is_object()) throw std::invalid_argument("each subscription must be an object");
      result.subscriptions.push_back({id_of(entry.value("id", Json()), "id"),
                                      id_of(entry.value("channelId", Json()), "channelId")});
    }
    return result;
  }
  if (name == "unsubscribe") {
    Unsubscribe result;
    for (const Json& id : member(message, "subscriptionIds", &Json::is_array, "an array")) {
      result.subscription_ids.push_back(id_of(id, "subscriptionIds[]"));
    }
    return result;
  }
  if (name == "advertise") {
    ClientAdvertise result;
    for (const Json& entry : member(message, "channels", &Json::is_array, "an array")) {
      if (!entry.is_object()) throw std::invalid_argument("each channel must be an object");
      result.channels.push_back({id_of(entry.value("id", Json()), "id"),
                                 member(entry, "topic", &Json::is_string, "a string").get<std::string>(),
                                 member(entry, "encoding", &Json::is_string, "a string").get<std::string>()});
    }
    return result;
  }
  if (name == "unadvertise") {
    ClientUnadvertise result;
    for (const Json& id : member(message, "channelIds", &Json::is_array, "an array")) {
      result.channel_ids.push_back(id_of(id, "channelIds[]"));
    }
    return result;
  }
  return ProtocolError{fmt::format("unsupported op \"{}\"", name.substr(0, 64))};
}

}  // namespace

bool client_publish_topic(std::string_view topic) {
  return topic == kCmdVelTopic || topic == kEstopTopic || topic == kReleaseTopic;
}

const std::vector<Channel>& channels() {
  static const std::vector<Channel> all = {
      {ChannelId::telemetry, "/wheeltec/telemetry", "wheeltec.Telemetry", telemetry_schema()},
      {ChannelId::status, "/wheeltec/status", "wheeltec.Status", status_schema()},
      {ChannelId::odom, "/wheeltec/odom", "foxglove.PoseInFrame", pose_schema()},
      {ChannelId::imu, "/wheeltec/imu", "wheeltec.Imu", imu_schema()},
  };
  return all;
}

std::string server_info(std::string_view session_id, const std::map<std::string, std::string>& metadata) {
  return Json{{"op", "serverInfo"},
              {"name", "wheeltec-web"},
              {"capabilities", {"clientPublish"}},
              {"supportedEncodings", {"json"}},
              {"metadata", metadata.empty() ? Json::object() : Json(metadata)},
              {"sessionId", session_id}}
      .dump();
}

std::string advertise() {
  Json list = Json::array();
  for (const Channel& channel : channels()) {
    list.push_back({{"id", static_cast<std::uint32_t>(channel.id)},
                    {"topic", channel.topic},
                    {"encoding", "json"},
                    {"schemaName", channel.schema_name},
                    {"schema", channel.schema},
                    {"schemaEncoding", "jsonschema"}});
  }
  return Json{{"op", "advertise"}, {"channels", list}}.dump();
}

std::string status(Level level, std::string_view message, std::string_view id) {
  Json object = {{"op", "status"}, {"level", static_cast<int>(level)}, {"message", message}};
  if (!id.empty()) object["id"] = id;
  return object.dump(-1, ' ', false, Json::error_handler_t::replace);
}

std::string message_data(std::uint32_t subscription_id, std::uint64_t timestamp, std::string_view payload) {
  std::string out;
  out.reserve(13 + payload.size());
  out.push_back('\x01');
  put_le(out, subscription_id, 4);
  put_le(out, timestamp, 8);
  out.append(payload);
  return out;
}

ClientMessage parse_text(std::string_view text) {
  auto read = read_json(text, "");
  if (auto* error = std::get_if<ProtocolError>(&read)) return std::move(*error);
  try {
    return parse_object(std::get<Json>(read));
  } catch (const std::exception& error) {
    return ProtocolError{error.what()};
  }
}

std::variant<ClientPublish, ProtocolError> parse_binary(std::string_view data) {
  if (data.empty()) return ProtocolError{"empty binary message"};
  if (data[0] != '\x01') {
    return ProtocolError{fmt::format("unsupported binary opcode 0x{:02x}", static_cast<unsigned char>(data[0]))};
  }
  if (data.size() < 5) return ProtocolError{"client publish shorter than its 5-byte header"};
  return ClientPublish{get_le32(data, 1), data.substr(5)};
}

std::variant<client::Velocity, ProtocolError> parse_cmd_vel(std::string_view payload) {
  auto read = read_json(payload, "cmd_vel: ");
  if (auto* error = std::get_if<ProtocolError>(&read)) return std::move(*error);
  client::Velocity velocity;
  if (auto problem = read_drive_velocity(std::get<Json>(read), velocity)) return ProtocolError{"cmd_vel: " + *problem};
  return velocity;
}

std::uint64_t timestamp_ns(double seconds) {
  if (!(seconds > 0.0) || !std::isfinite(seconds)) return 0;
  return static_cast<std::uint64_t>(std::llround(seconds * 1e9));
}

Json odom_pose(const client::Telemetry& record) {
  const double half = record.odom.yaw / 2.0;
  return {{"timestamp", time_of(record)},
          {"frame_id", "odom"},
          {"pose",
           {{"position", {{"x", record.odom.x}, {"y", record.odom.y}, {"z", 0.0}}},
            {"orientation", {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(half)}, {"w", std::cos(half)}}}}}};
}

Json imu(const client::Telemetry& record) {
  const client::Orientation q = record.orientation.value_or(client::Orientation{});
  return {{"timestamp", time_of(record)},
          {"frame_id", "base_link"},
          {"orientation", {{"x", q.x}, {"y", q.y}, {"z", q.z}, {"w", q.w}}},
          {"angular_velocity", {{"x", record.gyro.x}, {"y", record.gyro.y}, {"z", record.gyro.z}}},
          {"linear_acceleration", {{"x", record.accel.x}, {"y", record.accel.y}, {"z", record.accel.z}}}};
}

}  // namespace wheeltec::web::foxglove
