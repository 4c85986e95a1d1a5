#include "ros2_side/cmd_vel_writer.hpp"

#include <cstdint>
#include <stdexcept>

#include "geometry_msgs/msg/TwistPubSubTypes.h"
#include "geometry_msgs/msg/TwistStampedPubSubTypes.h"

namespace ros2_side {

namespace dds = eprosima::fastdds::dds;

geometry_msgs::msg::Twist make_twist(double vx, double vy, double wz) {
  geometry_msgs::msg::Twist twist;
  twist.linear().x(vx);
  twist.linear().y(vy);
  twist.angular().z(wz);
  return twist;
}

CmdVelWriter::CmdVelWriter(Participant& participant, const std::string& topic, Reliability reliability, int depth,
                           CmdVelMessage message)
    : participant_(participant), message_(message) {
  dds::TypeSupport type(message == CmdVelMessage::twist_stamped
                            ? static_cast<dds::TopicDataType*>(new geometry_msgs::msg::TwistStampedPubSubType())
                            : new geometry_msgs::msg::TwistPubSubType());
  auto& dds_topic = participant.topic(topic, type);
  writer_ = participant.publisher().create_datawriter(&dds_topic, writer_qos(reliability, depth), this);
  if (writer_ == nullptr) throw std::runtime_error("Fast DDS: cannot create a writer of " + topic);
}

CmdVelWriter::~CmdVelWriter() {
  writer_->set_listener(nullptr);
  participant_.publisher().delete_datawriter(writer_);
}

bool CmdVelWriter::wait_matched(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return matched_changed_.wait_for(lock, timeout, [&] { return matched_readers_ > 0; });
}

void CmdVelWriter::publish(const geometry_msgs::msg::Twist& twist) {
  bool written = false;
  if (message_ == CmdVelMessage::twist_stamped) {
    geometry_msgs::msg::TwistStamped stamped;
    const auto now = std::chrono::system_clock::now().time_since_epoch();
    const auto whole = std::chrono::duration_cast<std::chrono::seconds>(now);
    stamped.header().stamp().sec(static_cast<std::int32_t>(whole.count()));
    stamped.header().stamp().nanosec(
        static_cast<std::uint32_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(now - whole).count()));
    stamped.header().frame_id("base_link");
    stamped.twist(twist);
    written = writer_->write(&stamped);
  } else {
    geometry_msgs::msg::Twist copy = twist;
    written = writer_->write(&copy);
  }
  if (!written) throw std::runtime_error("Fast DDS: cmd_vel not written");
}

void CmdVelWriter::on_publication_matched(dds::DataWriter*, const dds::PublicationMatchedStatus& status) {
  {
    std::lock_guard lock(mutex_);
    matched_readers_ = status.current_count;
  }
  matched_changed_.notify_all();
}

RepeatingPublisher::RepeatingPublisher(CmdVelWriter& writer, geometry_msgs::msg::Twist twist,
                                       std::chrono::milliseconds period)
    : writer_(writer), thread_([this, twist, period] { run(twist, period); }) {}

RepeatingPublisher::~RepeatingPublisher() { stop(); }

std::chrono::system_clock::time_point RepeatingPublisher::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  stop_requested_.notify_all();
  if (thread_.joinable()) thread_.join();
  std::lock_guard lock(mutex_);
  return last_published_;
}

void RepeatingPublisher::run(geometry_msgs::msg::Twist twist, std::chrono::milliseconds period) {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    writer_.publish(twist);
    last_published_ = std::chrono::system_clock::now();
    stop_requested_.wait_for(lock, period, [&] { return stopping_; });
  }
}

}  // namespace ros2_side
