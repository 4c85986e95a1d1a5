#include "ros2_peer.hpp"

#include <optional>

#include "diagnostic_msgs/msg/DiagnosticArrayPubSubTypes.h"
#include "nav_msgs/msg/OdometryPubSubTypes.h"
#include "ros2_side/cmd_vel_writer.hpp"
#include "ros2_side/participant.hpp"
#include "ros2_side/qos_profiles.hpp"
#include "ros2_side/topic_reader.hpp"
#include "sensor_msgs/msg/ImuPubSubTypes.h"
#include "tf2_msgs/msg/TFMessagePubSubTypes.h"

namespace bench {
namespace {

std::int64_t ns_of(ros2_side::WallClock::time_point time) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(time.time_since_epoch()).count();
}

template <class Reader>
std::size_t count_between(const Reader* reader, std::int64_t from_ns, std::int64_t to_ns) {
  if (reader == nullptr) return 0;
  std::size_t count = 0;
  for (const auto& sample : reader->samples()) {
    const std::int64_t arrival = ns_of(sample.arrival);
    if (arrival >= from_ns && arrival < to_ns) ++count;
  }
  return count;
}

}  // namespace

struct Ros2Peer::Endpoints {
  Endpoints(int domain_id, bool all_readers, bool best_effort)
      : participant(domain_id),
        odom(participant, "rt/odom", best_effort ? ros2_side::RosQos::sensor_data : ros2_side::RosQos::default_profile),
        diagnostics(participant, "rt/diagnostics", ros2_side::RosQos::default_profile),
        cmd_vel(participant, "rt/cmd_vel", ros2_side::Reliability::reliable, 10) {
    if (all_readers) {
      imu.emplace(participant, "rt/imu", ros2_side::RosQos::sensor_data);
      tf.emplace(participant, "rt/tf", best_effort ? ros2_side::RosQos::sensor_data : ros2_side::RosQos::default_profile);
    }
  }

  ros2_side::Participant participant;
  ros2_side::TopicReader<nav_msgs::msg::OdometryPubSubType> odom;
  ros2_side::TopicReader<diagnostic_msgs::msg::DiagnosticArrayPubSubType> diagnostics;
  std::optional<ros2_side::TopicReader<sensor_msgs::msg::ImuPubSubType>> imu;
  std::optional<ros2_side::TopicReader<tf2_msgs::msg::TFMessagePubSubType>> tf;
  ros2_side::CmdVelWriter cmd_vel;
};

Ros2Peer::Ros2Peer(int domain_id, bool all_readers, bool best_effort)
    : endpoints_(std::make_unique<Endpoints>(domain_id, all_readers, best_effort)) {}

Ros2Peer::~Ros2Peer() = default;

bool Ros2Peer::wait_matched(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  auto left = [&] {
    return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
  };
  auto& e = *endpoints_;
  if (!e.odom.wait_matched(left()) || !e.diagnostics.wait_matched(left()) || !e.cmd_vel.wait_matched(left())) return false;
  if (e.imu && !e.imu->wait_matched(left())) return false;
  if (e.tf && !e.tf->wait_matched(left())) return false;
  return true;
}

bool Ros2Peer::wait_for_odom(std::chrono::milliseconds timeout) {
  return !endpoints_->odom.wait_for_count(1, timeout).empty();
}

std::vector<std::pair<std::int64_t, std::int64_t>> Ros2Peer::odom_receipts() const {
  std::vector<std::pair<std::int64_t, std::int64_t>> receipts;
  const auto samples = endpoints_->odom.samples();
  receipts.reserve(samples.size());
  for (const auto& sample : samples) {
    const auto& stamp = sample.message.header().stamp();
    const std::int64_t stamp_ns = static_cast<std::int64_t>(stamp.sec()) * 1'000'000'000 + stamp.nanosec();
    // The bridge turns the record's `time` (microseconds in the JSON) into sec and nanosec.
    receipts.emplace_back((stamp_ns + 500) / 1000, ns_of(sample.arrival));
  }
  return receipts;
}

std::size_t Ros2Peer::imu_samples(std::int64_t from_ns, std::int64_t to_ns) const {
  return count_between(endpoints_->imu ? &*endpoints_->imu : nullptr, from_ns, to_ns);
}

std::size_t Ros2Peer::tf_samples(std::int64_t from_ns, std::int64_t to_ns) const {
  return count_between(endpoints_->tf ? &*endpoints_->tf : nullptr, from_ns, to_ns);
}

nlohmann::json Ros2Peer::last_diagnostics() const {
  const auto samples = endpoints_->diagnostics.samples();
  if (samples.empty() || samples.back().message.status().empty()) return nullptr;
  const auto& status = samples.back().message.status().front();
  nlohmann::json values = nlohmann::json::object();
  for (const auto& pair : status.values()) values[pair.key()] = pair.value();
  return {{"name", status.name()}, {"level", status.level()}, {"message", status.message()}, {"values", values},
          {"messages_received", samples.size()}};
}

std::int64_t Ros2Peer::publish_cmd_vel(double vx) {
  const auto twist = ros2_side::make_twist(vx, 0.0, 0.0);
  const std::int64_t sent = ns_of(ros2_side::WallClock::now());
  endpoints_->cmd_vel.publish(twist);
  return sent;
}

}  // namespace bench
