#pragma once

#include <string>

#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>

namespace ros2_side {

// The rclcpp QoS profiles a ROS 2 subscriber uses for these topics (ros2/rmw qos_profiles.h),
// as rmw_fastrtps turns them into Fast DDS QoS.
enum class RosQos {
  default_profile,  // RELIABLE, KEEP_LAST 10, VOLATILE (teleop, QoS(10))
  sensor_data,      // BEST_EFFORT, KEEP_LAST 5, VOLATILE (robot_localization)
  system_default,   // Fast DDS's own default: BEST_EFFORT, KEEP_LAST 1 (nav2's OdomSmoother)
  latched,          // RELIABLE, KEEP_LAST 1, TRANSIENT_LOCAL (QoS(1).transient_local(): a latched state)
};

std::string to_string(RosQos profile);

eprosima::fastdds::dds::DataReaderQos reader_qos(RosQos profile);

enum class Reliability { reliable, best_effort };

// A ROS 2 publisher's writer: KEEP_LAST `depth`, VOLATILE.
eprosima::fastdds::dds::DataWriterQos writer_qos(Reliability reliability, int depth);

}  // namespace ros2_side
