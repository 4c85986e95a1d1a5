#include "socket_file.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "startup_error.hpp"

namespace wheeltec::daemon {
namespace {

std::string error_text(int error) { return std::strerror(error); }

// True if a process accepts (or queues) connections on the socket at `path`.
bool someone_listens(const std::string& path) {
  const int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) throw StartupError(fmt::format("cannot create a Unix socket: {}", error_text(errno)));
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::memcpy(address.sun_path, path.data(), path.size());
  const int result = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address));
  const int error = errno;
  ::close(fd);
  // EAGAIN: the listener's backlog is full, so it is alive.
  return result == 0 || error == EAGAIN || error == EINPROGRESS;
}

}  // namespace

void SocketFile::clear_stale(const std::string& path) {
  if (path.empty() || path.size() >= sizeof(sockaddr_un::sun_path)) {
    throw StartupError(fmt::format("socket path \"{}\": length must be 1 to {} bytes", path,
                                   sizeof(sockaddr_un::sun_path) - 1));
  }
  struct stat info {};
  if (::lstat(path.c_str(), &info) != 0) {
    if (errno == ENOENT) return;
    throw StartupError(fmt::format("socket {}: {}", path, error_text(errno)));
  }
  if (!S_ISSOCK(info.st_mode)) throw StartupError(fmt::format("socket {}: exists and is not a socket", path));
  if (someone_listens(path)) throw StartupError(fmt::format("socket {} in use by another running daemon", path));
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) {
    throw StartupError(fmt::format("cannot remove stale socket {}: {}", path, error_text(errno)));
  }
  spdlog::info("removed stale socket {}", path);
}

SocketFile::SocketFile(std::string path, mode_t mode, std::optional<gid_t> group) : path_(std::move(path)) {
  if (group && ::chown(path_.c_str(), static_cast<uid_t>(-1), *group) != 0) {
    const int error = errno;
    remove();
    throw StartupError(fmt::format("cannot set the group of socket {} to gid {}: {}", path_, *group, error_text(error)));
  }
  if (::chmod(path_.c_str(), mode) != 0) {
    const int error = errno;
    remove();
    throw StartupError(fmt::format("cannot set the mode of socket {} to {:04o}: {}", path_, mode, error_text(error)));
  }
}

SocketFile::~SocketFile() { remove(); }

void SocketFile::remove() {
  if (!present_) return;
  present_ = false;
  if (::unlink(path_.c_str()) != 0 && errno != ENOENT) {
    spdlog::warn("cannot remove socket {}: {}", path_, error_text(errno));
  }
}

}  // namespace wheeltec::daemon
