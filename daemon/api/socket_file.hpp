#pragma once

#include <sys/types.h>

#include <optional>
#include <string>

namespace wheeltec::daemon {

// The path of the API's Unix socket in the file system.
class SocketFile {
 public:
  // Makes the path free for bind(): a socket file nobody answers on is a leftover of a
  // daemon that died and is removed. Throws StartupError if a daemon answers on it or the
  // path is something other than a socket.
  static void clear_stale(const std::string& path);

  // Takes charge of a socket file just bound: sets its mode and group (StartupError on
  // failure) and removes it when destroyed or on remove().
  SocketFile(std::string path, mode_t mode, std::optional<gid_t> group);
  ~SocketFile();
  SocketFile(const SocketFile&) = delete;
  SocketFile& operator=(const SocketFile&) = delete;

  void remove();
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  bool present_ = true;
};

}  // namespace wheeltec::daemon
