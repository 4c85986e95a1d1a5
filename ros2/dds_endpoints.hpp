#pragma once

// Cyclone DDS's C API as a few RAII types: a participant on a domain, a topic's writer with
// ROS 2's QoS, and cmd_vel's reader. The only code here that calls Cyclone.

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include <dds/dds.h>

#include "ros2_messages.h"

namespace wheeltec::ros2 {

class DdsError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The Cyclone configuration of rmw_cyclonedds' localhost mode: discovery and data on
// 127.0.0.1 only, unicast, participants found by index (loopback has no multicast).
std::string localhost_configuration();

// A DDS domain participant. `configuration` (Cyclone's XML, or a list of XML fragments and
// file:// URIs) replaces CYCLONEDDS_URI's when given.
class DdsParticipant {
 public:
  DdsParticipant(int domain_id, const std::optional<std::string>& configuration);
  ~DdsParticipant();
  DdsParticipant(const DdsParticipant&) = delete;
  DdsParticipant& operator=(const DdsParticipant&) = delete;
  dds_entity_t handle() const { return participant_; }

 private:
  dds_entity_t domain_ = 0;  // set when this participant created the domain
  dds_entity_t participant_ = 0;
};

enum class Durability { volatile_, transient_local };

// RELIABLE, VOLATILE, KEEP_LAST `depth`, XCDR1: matches every QoS ROS 2 readers use.
// TRANSIENT_LOCAL (a latched state such as e_stop) keeps the last `depth` samples for
// readers that join later, and matches VOLATILE readers as well.
class DdsWriter {
 public:
  DdsWriter(const DdsParticipant& participant, const std::string& topic, const dds_topic_descriptor_t& type,
            int depth, Durability durability = Durability::volatile_);
  // False (and the reason in error()) when Cyclone refused the sample.
  bool write(const void* sample);
  std::string error() const { return error_; }

 private:
  dds_entity_t writer_ = 0;
  std::string error_;
};

// What cmd_vel carries: geometry_msgs/msg/Twist, or geometry_msgs/msg/TwistStamped (nav2's
// enable_stamped_cmd_vel), whose header is ignored.
enum class CmdVelType { twist, twist_stamped };

// cmd_vel: BEST_EFFORT, KEEP_LAST 1, matching reliable and best-effort writers alike. The
// handler runs on one of Cyclone's threads, once for each valid sample, with its Twist.
class CmdVelReader {
 public:
  using Handler = std::function<void(const geometry_msgs_msg_dds__Twist_&)>;
  CmdVelReader(const DdsParticipant& participant, const std::string& topic, CmdVelType type, Handler handler);
  // Returns once no handler runs any more.
  ~CmdVelReader();
  CmdVelReader(const CmdVelReader&) = delete;
  CmdVelReader& operator=(const CmdVelReader&) = delete;

 private:
  using TwistOf = const geometry_msgs_msg_dds__Twist_& (*)(const void* sample);
  static void on_data_available(dds_entity_t reader, void* self);
  Handler handler_;
  TwistOf twist_of_;
  dds_entity_t reader_ = 0;
};

// A topic of std_msgs/msg/Empty, each message a request (e_stop_trigger, e_stop_reset):
// RELIABLE, VOLATILE, KEEP_LAST 10, so that a single message from a ROS 2 publisher with
// the default or system-default profile is not lost (a BEST_EFFORT publisher does not
// match). The handler runs on one of Cyclone's threads, once for each valid sample.
class EmptyReader {
 public:
  using Handler = std::function<void()>;
  EmptyReader(const DdsParticipant& participant, const std::string& topic, Handler handler);
  // Returns once no handler runs any more.
  ~EmptyReader();
  EmptyReader(const EmptyReader&) = delete;
  EmptyReader& operator=(const EmptyReader&) = delete;

 private:
  static void on_data_available(dds_entity_t reader, void* self);
  Handler handler_;
  dds_entity_t reader_ = 0;
};

}  // namespace wheeltec::ros2
