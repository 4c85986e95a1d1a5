#include "ros2_side/participant.hpp"

#include <stdexcept>
#include <typeinfo>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

namespace ros2_side {
namespace {

namespace dds = eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::IPLocator;
using eprosima::fastrtps::rtps::Locator_t;

dds::DomainParticipantQos loopback_qos() {
  dds::DomainParticipantQos qos = dds::PARTICIPANT_QOS_DEFAULT;
  qos.name("wheeltec-ros2-tests");
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back("127.0.0.1");
  qos.transport().user_transports.push_back(udp);
  qos.transport().use_builtin_transports = false;
  Locator_t peer;
  peer.kind = LOCATOR_KIND_UDPv4;
  IPLocator::setIPv4(peer, 127, 0, 0, 1);
  qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  return qos;
}

}  // namespace

Participant::Participant(int domain_id) : domain_id_(domain_id) {
  auto* factory = dds::DomainParticipantFactory::get_instance();
  participant_ = factory->create_participant(static_cast<dds::DomainId_t>(domain_id), loopback_qos());
  if (participant_ == nullptr) {
    throw std::runtime_error("Fast DDS: no participant on domain " + std::to_string(domain_id));
  }
  subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
  publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  if (subscriber_ == nullptr || publisher_ == nullptr) {
    participant_->delete_contained_entities();
    factory->delete_participant(participant_);
    throw std::runtime_error("Fast DDS: no subscriber or publisher");
  }
}

Participant::~Participant() {
  participant_->delete_contained_entities();
  dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
}

dds::Topic& Participant::topic(const std::string& name, dds::TypeSupport type) {
  const dds::TypeSupport registered = participant_->find_type(type.get_type_name());
  if (registered.empty()) {
    type->auto_fill_type_object(false);
    type->auto_fill_type_information(false);
    if (participant_->register_type(type) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("Fast DDS: cannot register type " + type.get_type_name());
    }
  } else if (typeid(*registered.get()) != typeid(*type.get())) {
    // The raw-bytes Odometry and the typed one share a name: they need a participant each.
    throw std::logic_error("another type named " + type.get_type_name() + " is registered on this participant");
  }
  if (auto found = topics_.find(name); found != topics_.end()) {
    if (found->second->get_type_name() != type.get_type_name()) {
      throw std::logic_error("topic " + name + " already has type " + found->second->get_type_name());
    }
    return *found->second;
  }
  dds::Topic* topic = participant_->create_topic(name, type.get_type_name(), dds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) throw std::runtime_error("Fast DDS: cannot create topic " + name);
  topics_.emplace(name, topic);
  return *topic;
}

}  // namespace ros2_side
