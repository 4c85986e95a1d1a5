#include "dds_endpoints.hpp"

#include <memory>

#include <fmt/format.h>

namespace wheeltec::ros2 {
namespace {

struct QosDeleter {
  void operator()(dds_qos_t* qos) const { dds_delete_qos(qos); }
};
using Qos = std::unique_ptr<dds_qos_t, QosDeleter>;

Qos new_qos() { return Qos(dds_create_qos()); }

dds_entity_t check(dds_entity_t entity, const std::string& what) {
  if (entity < 0) throw DdsError(fmt::format("{}: {}", what, dds_strretcode(entity)));
  return entity;
}

// rmw_cyclonedds and rmw_fastrtps both speak XCDR1 only.
void set_xcdr1(dds_qos_t* qos) {
  const dds_data_representation_id_t xcdr1 = DDS_DATA_REPRESENTATION_XCDR1;
  dds_qset_data_representation(qos, 1, &xcdr1);
}

dds_entity_t topic_of(const DdsParticipant& participant, const std::string& topic, const dds_topic_descriptor_t& type) {
  return check(dds_create_topic(participant.handle(), &type, topic.c_str(), nullptr, nullptr),
               fmt::format("DDS topic {} ({})", topic, type.m_typename));
}

}  // namespace

std::string localhost_configuration() {
  return "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/>"
         "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
         "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>"
         "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery></Domain></CycloneDDS>";
}

DdsParticipant::DdsParticipant(int domain_id, const std::optional<std::string>& configuration) {
  const auto domain = static_cast<dds_domainid_t>(domain_id);
  if (configuration) {
    domain_ = check(dds_create_domain(domain, configuration->c_str()), fmt::format("DDS domain {}", domain_id));
  }
  // As rmw_cyclonedds marks its participants; ROS 2's graph tools read it.
  Qos qos = new_qos();
  static constexpr char kEnclave[] = "enclave=/;";
  dds_qset_userdata(qos.get(), kEnclave, sizeof kEnclave - 1);
  try {
    participant_ = check(dds_create_participant(domain, qos.get(), nullptr), fmt::format("DDS participant on domain {}", domain_id));
  } catch (...) {
    if (domain_ > 0) dds_delete(domain_);
    throw;
  }
}

DdsParticipant::~DdsParticipant() {
  dds_delete(participant_);
  if (domain_ > 0) dds_delete(domain_);
}

DdsWriter::DdsWriter(const DdsParticipant& participant, const std::string& topic, const dds_topic_descriptor_t& type,
                     int depth, Durability durability) {
  Qos qos = new_qos();
  // A KEEP_LAST writer drops its oldest sample rather than wait; the blocking time only bounds
  // a write while Cyclone's own buffers are full.
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(10));
  dds_qset_durability(qos.get(), durability == Durability::transient_local ? DDS_DURABILITY_TRANSIENT_LOCAL
                                                                            : DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, depth);
  set_xcdr1(qos.get());
  writer_ = check(dds_create_writer(participant.handle(), topic_of(participant, topic, type), qos.get(), nullptr),
                  fmt::format("DDS writer of {}", topic));
}

bool DdsWriter::write(const void* sample) {
  const dds_return_t result = dds_write(writer_, sample);
  if (result >= 0) return true;
  error_ = dds_strretcode(result);
  return false;
}

CmdVelReader::CmdVelReader(const DdsParticipant& participant, const std::string& topic, CmdVelType type,
                           Handler handler)
    : handler_(std::move(handler)) {
  const dds_topic_descriptor_t* descriptor = nullptr;
  if (type == CmdVelType::twist_stamped) {
    descriptor = &geometry_msgs_msg_dds__TwistStamped__desc;
    twist_of_ = [](const void* sample) -> const geometry_msgs_msg_dds__Twist_& {
      return static_cast<const geometry_msgs_msg_dds__TwistStamped_*>(sample)->twist_;
    };
  } else {
    descriptor = &geometry_msgs_msg_dds__Twist__desc;
    twist_of_ = [](const void* sample) -> const geometry_msgs_msg_dds__Twist_& {
      return *static_cast<const geometry_msgs_msg_dds__Twist_*>(sample);
    };
  }
  Qos qos = new_qos();
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 1);
  set_xcdr1(qos.get());
  dds_listener_t* listener = dds_create_listener(this);
  dds_lset_data_available(listener, &CmdVelReader::on_data_available);
  reader_ = dds_create_reader(participant.handle(), topic_of(participant, topic, *descriptor), qos.get(), listener);
  dds_delete_listener(listener);
  check(reader_, fmt::format("DDS reader of {}", topic));
}

CmdVelReader::~CmdVelReader() { dds_delete(reader_); }

void CmdVelReader::on_data_available(dds_entity_t reader, void* self) {
  auto& cmd_vel_reader = *static_cast<CmdVelReader*>(self);
  // Loaned samples (a null pointer asks for one): Cyclone owns what a TwistStamped's frame_id
  // allocates.
  for (;;) {
    void* samples[1] = {nullptr};
    dds_sample_info_t info{};
    if (dds_take(reader, samples, &info, 1, 1) <= 0) break;
    if (info.valid_data) cmd_vel_reader.handler_(cmd_vel_reader.twist_of_(samples[0]));
    dds_return_loan(reader, samples, 1);
  }
}

EmptyReader::EmptyReader(const DdsParticipant& participant, const std::string& topic, Handler handler)
    : handler_(std::move(handler)) {
  Qos qos = new_qos();
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, 10);
  set_xcdr1(qos.get());
  dds_listener_t* listener = dds_create_listener(this);
  dds_lset_data_available(listener, &EmptyReader::on_data_available);
  reader_ = dds_create_reader(participant.handle(), topic_of(participant, topic, std_msgs_msg_dds__Empty__desc),
                              qos.get(), listener);
  dds_delete_listener(listener);
  check(reader_, fmt::format("DDS reader of {}", topic));
}

EmptyReader::~EmptyReader() { dds_delete(reader_); }

void EmptyReader::on_data_available(dds_entity_t reader, void* self) {
  auto& empty_reader = *static_cast<EmptyReader*>(self);
  for (;;) {
    void* samples[1] = {nullptr};
    dds_sample_info_t info{};
    if (dds_take(reader, samples, &info, 1, 1) <= 0) break;
    const bool valid = info.valid_data;
    dds_return_loan(reader, samples, 1);
    if (valid) empty_reader.handler_();
  }
}

}  // namespace wheeltec::ros2
