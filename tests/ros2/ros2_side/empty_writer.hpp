#pragma once

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/DataWriterListener.hpp>

#include "ros2_side/participant.hpp"
#include "ros2_side/qos_profiles.hpp"

namespace ros2_side {

// A ROS 2 publisher of std_msgs/msg/Empty on `topic` ("rt/e_stop_trigger"), as
// `ros2 topic pub --once /e_stop_trigger std_msgs/msg/Empty` or a safety node sends it.
class EmptyWriter : private eprosima::fastdds::dds::DataWriterListener {
 public:
  EmptyWriter(Participant& participant, const std::string& topic, Reliability reliability = Reliability::reliable,
              int depth = 10);
  ~EmptyWriter() override;
  EmptyWriter(const EmptyWriter&) = delete;
  EmptyWriter& operator=(const EmptyWriter&) = delete;

  // Whether a reader of the topic has matched within `timeout`.
  bool wait_matched(std::chrono::milliseconds timeout);
  void publish();

 private:
  void on_publication_matched(eprosima::fastdds::dds::DataWriter* writer,
                              const eprosima::fastdds::dds::PublicationMatchedStatus& status) override;

  Participant& participant_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
  std::mutex mutex_;
  std::condition_variable matched_changed_;
  int matched_readers_ = 0;
};

}  // namespace ros2_side
