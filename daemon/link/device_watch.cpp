#include "device_watch.hpp"

#include <sys/inotify.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <spdlog/spdlog.h>

namespace wheeltec::daemon {

DeviceWatch::DeviceWatch(boost::asio::io_context& io, std::string path) : inotify_(io) {
  const std::filesystem::path device(path);
  directory_ = device.parent_path().empty() ? "." : device.parent_path().string();
  name_ = device.filename().string();
}

bool DeviceWatch::start(std::function<void()> appeared) {
  appeared_ = std::move(appeared);
  const int fd = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd < 0) {
    spdlog::debug("serial: no inotify ({}); reopening on a timer only", std::strerror(errno));
    return false;
  }
  if (::inotify_add_watch(fd, directory_.c_str(), IN_CREATE | IN_MOVED_TO | IN_ATTRIB) < 0) {
    spdlog::debug("serial: cannot watch {} ({}); reopening on a timer only", directory_, std::strerror(errno));
    ::close(fd);
    return false;
  }
  inotify_.assign(fd);
  read();
  return true;
}

void DeviceWatch::stop() {
  boost::system::error_code ignored;
  inotify_.close(ignored);
}

void DeviceWatch::read() {
  inotify_.async_read_some(boost::asio::buffer(buffer_), [this](const boost::system::error_code& ec, std::size_t n) {
    if (ec) return;  // closed, or the watch is gone: the retry timer remains
    bool ours = false;
    for (std::size_t at = 0; at + sizeof(inotify_event) <= n;) {
      inotify_event event;
      std::memcpy(&event, buffer_.data() + at, sizeof(event));
      const char* name = buffer_.data() + at + sizeof(inotify_event);
      if (event.len > 0 && name_ == std::string(name, ::strnlen(name, event.len))) ours = true;
      at += sizeof(inotify_event) + event.len;
    }
    if (ours && appeared_) appeared_();
    read();
  });
}

}  // namespace wheeltec::daemon
