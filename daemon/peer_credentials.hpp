#pragma once

#include <sys/types.h>

#include <optional>
#include <vector>

namespace wheeltec::daemon {

// Who is on the other end of a connected Unix socket, as the kernel saw it at connect time.
struct PeerCredentials {
  pid_t pid = 0;
  uid_t uid = 0;
  gid_t gid = 0;                    // primary group
  std::vector<gid_t> supplementary;  // from /proc/<pid>/status; empty if the process is gone
};

// SO_PEERCRED plus the supplementary groups; empty if the kernel does not tell.
std::optional<PeerCredentials> read_peer_credentials(int socket_fd);

// Parses the "Groups:" line of a /proc/<pid>/status text.
std::vector<gid_t> parse_proc_status_groups(const char* status_text);

}  // namespace wheeltec::daemon
