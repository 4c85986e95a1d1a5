#pragma once

#include <cstdint>
#include <vector>

#include <fastdds/dds/topic/TopicDataType.hpp>

namespace ros2_side {

// One sample's serialized payload as it came over the wire, encapsulation header included.
struct SerializedSample {
  std::vector<std::uint8_t> bytes;
};

// A type registered as nav_msgs::msg::dds_::Odometry_ that does not decode: a reader of it
// keeps each sample's bytes, for a decoder other than Fast CDR to check.
class RawOdometryType : public eprosima::fastdds::dds::TopicDataType {
 public:
  using type = SerializedSample;

  RawOdometryType();

  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override;
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override;
  std::function<uint32_t()> getSerializedSizeProvider(void* data) override;
  void* createData() override;
  void deleteData(void* data) override;
  bool getKey(void* data, eprosima::fastrtps::rtps::InstanceHandle_t* handle, bool force_md5) override;
};

}  // namespace ros2_side
