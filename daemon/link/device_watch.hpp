#pragma once

#include <array>
#include <functional>
#include <string>

#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>

namespace wheeltec::daemon {

// Tells when a name may have (re)appeared at a path: an inotify watch on the path's
// directory for entries created, moved in or changed there under that name (udev
// re-creating /dev/wheeltec_controller, a test renaming a new pty's link over the old).
// A hint only: events can be missed, so its user retries on a timer as well.
class DeviceWatch {
 public:
  DeviceWatch(boost::asio::io_context& io, std::string path);

  // False (logged at debug level) when the directory cannot be watched.
  bool start(std::function<void()> appeared);
  void stop();

 private:
  void read();

  std::string directory_;
  std::string name_;
  boost::asio::posix::stream_descriptor inotify_;
  alignas(8) std::array<char, 4096> buffer_{};
  std::function<void()> appeared_;
};

}  // namespace wheeltec::daemon
