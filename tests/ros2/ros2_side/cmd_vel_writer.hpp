#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>

#include "geometry_msgs/msg/Twist.h"
#include "ros2_side/participant.hpp"
#include "ros2_side/qos_profiles.hpp"

namespace ros2_side {

geometry_msgs::msg::Twist make_twist(double vx, double vy, double wz);

// What a cmd_vel publisher sends: Twist (teleop, nav2 on Jazzy by default) or TwistStamped
// (nav2 on Kilted, or enable_stamped_cmd_vel).
enum class CmdVelMessage { twist, twist_stamped };

// A ROS 2 publisher of cmd_vel on `topic` ("rt/cmd_vel"); as TwistStamped, each Twist goes
// out with a header as nav2 stamps it (now, frame base_link).
class CmdVelWriter : private eprosima::fastdds::dds::DataWriterListener {
 public:
  CmdVelWriter(Participant& participant, const std::string& topic, Reliability reliability, int depth,
               CmdVelMessage message = CmdVelMessage::twist);
  ~CmdVelWriter() override;
  CmdVelWriter(const CmdVelWriter&) = delete;
  CmdVelWriter& operator=(const CmdVelWriter&) = delete;

  // Whether a reader of the topic has matched within `timeout`.
  bool wait_matched(std::chrono::milliseconds timeout);
  void publish(const geometry_msgs::msg::Twist& twist);

 private:
  void on_publication_matched(eprosima::fastdds::dds::DataWriter* writer,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& status) override;

  Participant& participant_;
  CmdVelMessage message_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  std::mutex mutex_;
  std::condition_variable matched_changed_;
  int matched_readers_ = 0;
};

// Publishes one Twist every `period` on its own thread, as teleop and nav2 do, until stopped.
class RepeatingPublisher {
 public:
  RepeatingPublisher(CmdVelWriter& writer, geometry_msgs::msg::Twist twist, std::chrono::milliseconds period);
  ~RepeatingPublisher();
  RepeatingPublisher(const RepeatingPublisher&) = delete;
  RepeatingPublisher& operator=(const RepeatingPublisher&) = delete;

  // Stops publishing and returns when the last message was published.
  std::chrono::system_clock::time_point stop();

 private:
  void run(geometry_msgs::msg::Twist twist, std::chrono::milliseconds period);

  CmdVelWriter& writer_;
  std::mutex mutex_;
  std::condition_variable stop_requested_;
  bool stopping_ = false;
  std::chrono::system_clock::time_point last_published_;
  std::thread thread_;
};

}  // namespace ros2_side
