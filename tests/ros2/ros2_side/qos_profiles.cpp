#include "ros2_side/qos_profiles.hpp"

namespace ros2_side {
namespace {

namespace dds = eprosima::fastdds::dds;

template <class Qos>
void set_history(Qos& qos, int depth) {
  qos.history().kind = dds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = depth;
}

// Payloads as large as each sample. rmw_fastrtps preallocates with reallocation, starting from
// its type support's small sizes; fastddsgen's types declare the size of 100-element sequences
// of 255-character strings instead (5 MB for a DiagnosticArray), which a preallocating reader
// would reserve for every sample it keeps.
void set_payload_memory(dds::DataReaderQos& qos) {
  qos.endpoint().history_memory_policy = eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
}

}  // namespace

std::string to_string(RosQos profile) {
  switch (profile) {
    case RosQos::default_profile: return "default";
    case RosQos::sensor_data: return "sensor_data";
    case RosQos::system_default: return "system_default";
    case RosQos::latched: return "latched";
  }
  return "?";
}

dds::DataReaderQos reader_qos(RosQos profile) {
  dds::DataReaderQos qos = dds::DATAREADER_QOS_DEFAULT;
  // XCDR1 only, whatever the profile, as rmw_fastrtps.
  qos.type_consistency().representation.m_value = {dds::XCDR_DATA_REPRESENTATION};
  set_payload_memory(qos);
  switch (profile) {
    case RosQos::default_profile:
      qos.reliability().kind = dds::RELIABLE_RELIABILITY_QOS;
      qos.durability().kind = dds::VOLATILE_DURABILITY_QOS;
      set_history(qos, 10);
      break;
    case RosQos::sensor_data:
      qos.reliability().kind = dds::BEST_EFFORT_RELIABILITY_QOS;
      qos.durability().kind = dds::VOLATILE_DURABILITY_QOS;
      set_history(qos, 5);
      break;
    case RosQos::system_default:
      break;
    case RosQos::latched:
      qos.reliability().kind = dds::RELIABLE_RELIABILITY_QOS;
      qos.durability().kind = dds::TRANSIENT_LOCAL_DURABILITY_QOS;
      set_history(qos, 1);
      break;
  }
  return qos;
}

dds::DataWriterQos writer_qos(Reliability reliability, int depth) {
  dds::DataWriterQos qos = dds::DATAWRITER_QOS_DEFAULT;
  qos.representation().m_value = {dds::XCDR_DATA_REPRESENTATION};
  qos.reliability().kind =
      reliability == Reliability::reliable ? dds::RELIABLE_RELIABILITY_QOS : dds::BEST_EFFORT_RELIABILITY_QOS;
  qos.durability().kind = dds::VOLATILE_DURABILITY_QOS;
  set_history(qos, depth);
  return qos;
}

}  // namespace ros2_side
