#include "channels.hpp"

#include <cmath>

#include "schemas.hpp"

namespace wheeltec::record {
namespace {

struct OdomPose {
  RealtimeNanos time;
  double x, y, yaw;
};

std::optional<double> finite_number(const Json& object, const char* key) {
  const auto found = object.find(key);
  if (found == object.end() || !found->is_number()) return std::nullopt;
  const double value = found->get<double>();
  return std::isfinite(value) ? std::optional(value) : std::nullopt;
}

std::optional<OdomPose> odom_pose_of(const Json& record) {
  const auto time = time_of_message(record);
  if (!time) return std::nullopt;
  const auto odom = record.find("odom");
  if (odom == record.end() || !odom->is_object()) return std::nullopt;
  const auto x = finite_number(*odom, "x"), y = finite_number(*odom, "y"), yaw = finite_number(*odom, "yaw");
  if (!x || !y || !yaw) return std::nullopt;
  return OdomPose{*time, *x, *y, *yaw};
}

Json timestamp_of(RealtimeNanos time) {
  const long long ns = time.time_since_epoch().count();
  return {{"sec", ns / 1'000'000'000}, {"nsec", ns % 1'000'000'000}};
}

Json position_of(const OdomPose& pose) { return {{"x", pose.x}, {"y", pose.y}, {"z", 0.0}}; }

// A rotation of `yaw` about z.
Json quaternion_of(const OdomPose& pose) {
  return {{"x", 0.0}, {"y", 0.0}, {"z", std::sin(pose.yaw / 2.0)}, {"w", std::cos(pose.yaw / 2.0)}};
}

}  // namespace

const std::array<ChannelSpec, 5>& channels() {
  static const std::array<ChannelSpec, 5> all{{
      {Channel::telemetry, "/telemetry", "wheeltec.Telemetry", schemas::telemetry},
      {Channel::status, "/status", "wheeltec.Status", schemas::status},
      {Channel::events, "/events", "wheeltec.Event", schemas::event},
      {Channel::odom, "/odom", "foxglove.PoseInFrame", schemas::pose_in_frame},
      {Channel::tf, "/tf", "foxglove.FrameTransform", schemas::frame_transform},
  }};
  return all;
}

const ChannelSpec& channel_spec(Channel channel) { return channels().at(static_cast<std::size_t>(channel)); }

std::optional<Json> odom_pose_in_frame(const Json& record) {
  const auto pose = odom_pose_of(record);
  if (!pose) return std::nullopt;
  return Json{{"timestamp", timestamp_of(pose->time)},
              {"frame_id", kOdomFrame},
              {"pose", {{"position", position_of(*pose)}, {"orientation", quaternion_of(*pose)}}}};
}

std::optional<Json> odom_frame_transform(const Json& record) {
  const auto pose = odom_pose_of(record);
  if (!pose) return std::nullopt;
  return Json{{"timestamp", timestamp_of(pose->time)},
              {"parent_frame_id", kOdomFrame},
              {"child_frame_id", kBaseFrame},
              {"translation", position_of(*pose)},
              {"rotation", quaternion_of(*pose)}};
}

}  // namespace wheeltec::record
