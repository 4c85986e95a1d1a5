#include "ros2_side/empty_writer.hpp"

#include <stdexcept>

#include "std_msgs/msg/EmptyPubSubTypes.h"

namespace ros2_side {

namespace dds = eprosima::fastdds::dds;

EmptyWriter::EmptyWriter(Participant& participant, const std::string& topic, Reliability reliability, int depth)
    : participant_(participant) {
  auto& dds_topic = participant.topic(topic, dds::TypeSupport(new std_msgs::msg::EmptyPubSubType()));
  writer_ = participant.publisher().create_datawriter(&dds_topic, writer_qos(reliability, depth), this);
  if (writer_ == nullptr) throw std::runtime_error("Fast DDS: cannot create a writer of " + topic);
}

EmptyWriter::~EmptyWriter() {
  writer_->set_listener(nullptr);
  participant_.publisher().delete_datawriter(writer_);
}

bool EmptyWriter::wait_matched(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  return matched_changed_.wait_for(lock, timeout, [&] { return matched_readers_ > 0; });
}

void EmptyWriter::publish() {
  std_msgs::msg::Empty message;
  if (!writer_->write(&message)) throw std::runtime_error("Fast DDS: Empty not written");
}

void EmptyWriter::on_publication_matched(dds::DataWriter*, const dds::PublicationMatchedStatus& status) {
  {
    std::lock_guard lock(mutex_);
    matched_readers_ = status.current_count;
  }
  matched_changed_.notify_all();
}

}  // namespace ros2_side
