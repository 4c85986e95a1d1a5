#pragma once

#include <sys/types.h>

#include <optional>
#include <vector>

namespace wheeltec::daemon {

// Who is on the other end of a connected Unix socket, as the kernel recorded it when the
// peer connected. Nothing here reads /proc: a service with ProtectProc=invisible cannot see
// other users' processes there, and a pid can be reused between connect and the read.
struct PeerCredentials {
  pid_t pid = 0;
  uid_t uid = 0;
  gid_t gid = 0;                     // primary group
  std::vector<gid_t> supplementary;  // SO_PEERGROUPS
};

// SO_PEERCRED and SO_PEERGROUPS; empty if the kernel does not tell.
std::optional<PeerCredentials> read_peer_credentials(int socket_fd);

}  // namespace wheeltec::daemon
