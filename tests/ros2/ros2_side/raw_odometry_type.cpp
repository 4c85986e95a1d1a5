#include "ros2_side/raw_odometry_type.hpp"

#include <cstring>

namespace ros2_side {

RawOdometryType::RawOdometryType() {
  setName("nav_msgs::msg::dds_::Odometry_");
  // An Odometry with short frame names takes about 720 bytes; readers allocate each sample's size.
  m_typeSize = 1024;
  m_isGetKeyDefined = false;
}

bool RawOdometryType::serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) {
  const auto& sample = *static_cast<SerializedSample*>(data);
  if (sample.bytes.size() > payload->max_size) return false;
  std::memcpy(payload->data, sample.bytes.data(), sample.bytes.size());
  payload->length = static_cast<uint32_t>(sample.bytes.size());
  return true;
}

bool RawOdometryType::deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) {
  auto& sample = *static_cast<SerializedSample*>(data);
  sample.bytes.assign(payload->data, payload->data + payload->length);
  return true;
}

std::function<uint32_t()> RawOdometryType::getSerializedSizeProvider(void* data) {
  return [data] { return static_cast<uint32_t>(static_cast<SerializedSample*>(data)->bytes.size()); };
}

void* RawOdometryType::createData() { return new SerializedSample(); }

void RawOdometryType::deleteData(void* data) { delete static_cast<SerializedSample*>(data); }

bool RawOdometryType::getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) { return false; }

}  // namespace ros2_side
