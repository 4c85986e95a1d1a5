#include "peer_credentials.hpp"

#include <sys/socket.h>

#include <cerrno>

namespace wheeltec::daemon {
namespace {

// The peer's supplementary groups as they were at connect time (Linux 4.13 and later).
// The kernel answers ERANGE with the size it needs when the buffer is too small.
std::optional<std::vector<gid_t>> read_peer_groups(int socket_fd) {
  std::vector<gid_t> groups(32);
  for (;;) {
    socklen_t length = static_cast<socklen_t>(groups.size() * sizeof(gid_t));
    if (::getsockopt(socket_fd, SOL_SOCKET, SO_PEERGROUPS, groups.data(), &length) == 0) {
      groups.resize(length / sizeof(gid_t));
      return groups;
    }
    if (errno != ERANGE || length <= groups.size() * sizeof(gid_t)) return std::nullopt;
    groups.resize(length / sizeof(gid_t));
  }
}

}  // namespace

std::optional<PeerCredentials> read_peer_credentials(int socket_fd) {
  ucred credentials{};
  socklen_t length = sizeof(credentials);
  if (::getsockopt(socket_fd, SOL_SOCKET, SO_PEERCRED, &credentials, &length) != 0 || length != sizeof(credentials)) {
    return std::nullopt;
  }
  auto groups = read_peer_groups(socket_fd);
  if (!groups) return std::nullopt;
  return PeerCredentials{credentials.pid, credentials.uid, credentials.gid, std::move(*groups)};
}

}  // namespace wheeltec::daemon
