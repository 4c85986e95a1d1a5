#include "peer_credentials.hpp"

#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cstdlib>
#include <cstring>
#include <string>

namespace wheeltec::daemon {
namespace {

// /proc/<pid>/status is a few KiB; the Groups: line comes early, well within this.
constexpr std::size_t kStatusReadBytes = 16 * 1024;

std::vector<gid_t> read_supplementary_groups(pid_t pid) {
  const std::string path = "/proc/" + std::to_string(pid) + "/status";
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return {};
  std::string text(kStatusReadBytes, '\0');
  std::size_t length = 0;
  while (length + 1 < text.size()) {
    const ssize_t n = ::read(fd, text.data() + length, text.size() - 1 - length);
    if (n <= 0) break;
    length += static_cast<std::size_t>(n);
  }
  ::close(fd);
  text.resize(length);
  return parse_proc_status_groups(text.c_str());
}

}  // namespace

std::vector<gid_t> parse_proc_status_groups(const char* status_text) {
  std::vector<gid_t> groups;
  const char* line = status_text;
  while (line != nullptr && *line != '\0') {
    if (std::strncmp(line, "Groups:", 7) == 0) {
      const char* cursor = line + 7;
      for (;;) {
        while (*cursor == ' ' || *cursor == '\t') ++cursor;
        if (*cursor < '0' || *cursor > '9') break;
        char* end = nullptr;
        const unsigned long value = std::strtoul(cursor, &end, 10);
        groups.push_back(static_cast<gid_t>(value));
        cursor = end;
      }
      break;
    }
    line = std::strchr(line, '\n');
    if (line != nullptr) ++line;
  }
  return groups;
}

std::optional<PeerCredentials> read_peer_credentials(int socket_fd) {
  ucred credentials{};
  socklen_t length = sizeof(credentials);
  if (::getsockopt(socket_fd, SOL_SOCKET, SO_PEERCRED, &credentials, &length) != 0 || length != sizeof(credentials)) {
    return std::nullopt;
  }
  PeerCredentials peer;
  peer.pid = credentials.pid;
  peer.uid = credentials.uid;
  peer.gid = credentials.gid;
  if (credentials.pid > 0) peer.supplementary = read_supplementary_groups(credentials.pid);
  return peer;
}

}  // namespace wheeltec::daemon
