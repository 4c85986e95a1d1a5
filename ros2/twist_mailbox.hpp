#pragma once

// cmd_vel's hand-over from Cyclone's receive thread to the bridge's one Asio thread: the
// newest drive waits, and a burst faster than the bridge takes them costs no memory (an
// older waiting drive is replaced, as the daemon's would be anyway). Every Twist is counted,
// and one with a non-finite value is dropped here, so that it never replaces a good one.

#include <cstdint>
#include <mutex>
#include <optional>
#include <utility>

#include "wheeltec/client/records.hpp"

#include "messages.hpp"

namespace wheeltec::ros2 {

class TwistMailbox {
 public:
  // Cyclone's thread: true when the mailbox was empty, so the taker is to be woken.
  bool put(const geometry_msgs_msg_dds__Twist_& twist) {
    const std::optional<client::Velocity> velocity = drive_of(twist);
    std::lock_guard lock(mutex_);
    const bool was_empty = !mail_.received;
    ++mail_.received;
    if (velocity) mail_.drive = velocity;
    else ++mail_.non_finite;
    return was_empty;
  }

  struct Mail {
    std::optional<client::Velocity> drive;  // the newest good one
    std::uint64_t received = 0;             // Twists put since the last take
    std::uint64_t non_finite = 0;           // of which dropped
  };
  // The bridge's thread: what was put since the last take.
  Mail take() {
    std::lock_guard lock(mutex_);
    return std::exchange(mail_, Mail{});
  }

 private:
  std::mutex mutex_;
  Mail mail_;
};

}  // namespace wheeltec::ros2
