// The daemon's default api.socket and the client library's default are one path: the
// installed client library cannot depend on the daemon's config code, so this test holds
// them together.
#include <gtest/gtest.h>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/config/config.hpp"

TEST(DefaultSocket, TheClientLibraryLooksWhereTheDaemonListens) {
  EXPECT_EQ(wheeltec::GatewayConfig{}.api.socket, wheeltec::client::kDefaultSocketPath);
}
