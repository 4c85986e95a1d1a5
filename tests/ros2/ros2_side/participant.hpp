#pragma once

#include <map>
#include <memory>
#include <string>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

namespace ros2_side {

// A DDS participant on one domain that sees only 127.0.0.1: UDPv4 on loopback, no built-in
// transports, initial peer 127.0.0.1 (the Fast DDS half of the localhost setup in
// ros2-notes.md), with one subscriber and one publisher for every reader and writer.
class Participant {
 public:
  explicit Participant(int domain_id);
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  int domain_id() const { return domain_id_; }
  eprosima::fastdds::dds::Subscriber& subscriber() { return *subscriber_; }
  eprosima::fastdds::dds::Publisher& publisher() { return *publisher_; }

  // The topic `name` ("rt/odom") of `type`, created on first use. Its type is registered
  // as rmw_fastrtps registers its types: without type object or type information.
  // Throws when the topic exists with another type.
  eprosima::fastdds::dds::Topic& topic(const std::string& name, eprosima::fastdds::dds::TypeSupport type);

 private:
  int domain_id_;
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

}  // namespace ros2_side
