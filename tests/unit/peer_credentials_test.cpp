// Who may drive is decided from what the kernel recorded when the client connected
// (SO_PEERCRED, SO_PEERGROUPS), never from /proc, which a service with
// ProtectProc=invisible cannot read for other users' processes.

#include <grp.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>

#include "api/control_policy.hpp"
#include "api/peer_credentials.hpp"

namespace {

using wheeltec::daemon::ControlPolicy;
using wheeltec::daemon::PeerCredentials;
using wheeltec::daemon::read_peer_credentials;

constexpr uid_t kNobody = 65534;
constexpr gid_t kPrimaryGroup = 4141;
constexpr gid_t kSupplementaryGroups[] = {4242, 4343};

bool contains(const std::vector<gid_t>& groups, gid_t gid) {
  return std::find(groups.begin(), groups.end(), gid) != groups.end();
}

TEST(PeerCredentials, SupplementaryGroupsComeFromTheKernelAsAtConnect) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give the connecting process other credentials";
  const int listener = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(listener, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const std::string name = "wheeltec-peer-credentials-test-" + std::to_string(::getpid());
  std::memcpy(address.sun_path + 1, name.data(), name.size());  // abstract: no file to clean up
  const auto length = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + 1 + name.size());
  ASSERT_EQ(::bind(listener, reinterpret_cast<sockaddr*>(&address), length), 0);
  ASSERT_EQ(::listen(listener, 1), 0);

  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    // A user who joined two groups besides its primary one, as `usermod -aG` leaves them.
    if (::setgroups(2, kSupplementaryGroups) != 0 || ::setgid(kPrimaryGroup) != 0 || ::setuid(kNobody) != 0) _exit(2);
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    _exit(::connect(fd, reinterpret_cast<sockaddr*>(&address), length) == 0 ? 0 : 3);
  }
  // The client is gone (its /proc entry with it, its pid free for reuse) before the
  // connection is accepted: what the kernel recorded at connect time still answers.
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "child status " << status;
  const int connection = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
  ASSERT_GE(connection, 0);
  const auto peer = read_peer_credentials(connection);
  ::close(connection);
  ::close(listener);

  ASSERT_TRUE(peer.has_value());
  EXPECT_EQ(peer->pid, child);
  EXPECT_EQ(peer->uid, kNobody);
  EXPECT_EQ(peer->gid, kPrimaryGroup);
  EXPECT_TRUE(contains(peer->supplementary, kSupplementaryGroups[0]));
  EXPECT_TRUE(contains(peer->supplementary, kSupplementaryGroups[1]));
}

TEST(ControlPolicy, AMemberOfAControlGroupThroughASupplementaryGroupMayDrive) {
  wheeltec::GatewayConfig::Api api;
  api.control_groups = {"root"};  // gid 0 exists everywhere
  const ControlPolicy policy(api, /*daemon_uid=*/999);
  EXPECT_FALSE(policy.refusal(PeerCredentials{1, kNobody, kPrimaryGroup, {4242, 0}}).has_value());
  EXPECT_FALSE(policy.refusal(PeerCredentials{1, kNobody, 0, {}}).has_value()) << "primary group";
  const auto refused = policy.refusal(PeerCredentials{1, kNobody, kPrimaryGroup, {4242}});
  ASSERT_TRUE(refused.has_value());
  EXPECT_NE(refused->find("api.control_groups"), std::string::npos) << *refused;
}

TEST(ControlPolicy, RootAndTheDaemonsOwnUserMayDriveWithoutBeingListed) {
  const ControlPolicy policy(wheeltec::GatewayConfig::Api{}, /*daemon_uid=*/999);
  EXPECT_FALSE(policy.refusal(PeerCredentials{1, 0, 0, {}}).has_value());
  EXPECT_FALSE(policy.refusal(PeerCredentials{1, 999, 999, {}}).has_value());
  EXPECT_TRUE(policy.refusal(PeerCredentials{1, kNobody, kNobody, {}}).has_value());
}

}  // namespace
