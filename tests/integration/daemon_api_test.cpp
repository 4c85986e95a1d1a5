// Bad input on the JSON-RPC socket: every class of error in the contract gets its
// code, the connection stays usable, and nothing reaches the bus. An over-long line
// costs only its own connection.

#include <gtest/gtest.h>

#include "wheeltec/version.hpp"
#include "can_bus.hpp"
#include "control_frames.hpp"
#include "shared_gateway.hpp"

namespace integration {
namespace {

using namespace std::chrono_literals;

class DaemonApi : public SharedGatewayTest {
 protected:
  static void SetUpTestSuite() { start_shared(GatewayOptions{}); }
  static void TearDownTestSuite() { stop_shared(); }

  // Sends `line` and checks that the response with `id` is the error `code`.
  static void expect_error(RpcConnection& client, const std::string& line, const Json& id, int code) {
    const Json response = client.request_line(line, id);
    EXPECT_EQ(response["jsonrpc"], "2.0") << line << " -> " << response.dump();
    EXPECT_FALSE(response.contains("result")) << line << " -> " << response.dump();
    ASSERT_TRUE(response["error"].is_object()) << line << " -> " << response.dump();
    EXPECT_EQ(response["error"]["code"], code) << line << " -> " << response.dump();
    EXPECT_TRUE(response["error"]["message"].is_string() && !response["error"]["message"].get<std::string>().empty())
        << line << " -> " << response.dump();
    EXPECT_EQ(client.call("version")["protocol"], wheeltec::kProtocolVersion) << "the connection must stay usable after: " << line;
  }
};

TEST_F(DaemonApi, UnparsableLineIsAParseError) {
  auto client = gateway().connect();
  expect_error(client, R"({"jsonrpc":"2.0","id":1,"method":"status")", nullptr, -32700);
  expect_error(client, "{not json", nullptr, -32700);
  expect_error(client, "\xff\xfe garbage", nullptr, -32700);
}

TEST_F(DaemonApi, InvalidRequestsAreRejected) {
  auto client = gateway().connect();
  expect_error(client, "[1,2,3]", nullptr, -32600);
  expect_error(client, R"("status")", nullptr, -32600);
  expect_error(client, "42", nullptr, -32600);
  expect_error(client, R"({"id":7,"method":"status"})", 7, -32600);
  expect_error(client, R"({"jsonrpc":"1.0","id":8,"method":"status"})", 8, -32600);
  expect_error(client, R"({"jsonrpc":"2.0","id":9})", 9, -32600);
  expect_error(client, R"({"jsonrpc":"2.0","id":"ten","method":5})", "ten", -32600);
}

TEST_F(DaemonApi, UnknownMethodIsMethodNotFound) {
  auto client = gateway().connect();
  expect_error(client, R"({"jsonrpc":"2.0","id":11,"method":"fly"})", 11, -32601);
  expect_error(client, R"({"jsonrpc":"2.0","id":12,"method":"STATUS"})", 12, -32601);
}

TEST_F(DaemonApi, BadParamsAreInvalidParamsAndDoNotDrive) {
  CanBus bus(test_interface());
  auto client = gateway().connect();
  expect_error(client, R"({"jsonrpc":"2.0","id":20,"method":"drive","params":{"vx":"fast"}})", 20, -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":21,"method":"drive","params":{"vx":null}})", 21, -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":22,"method":"drive","params":{"vx":true}})", 22, -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":23,"method":"drive","params":{"vx":0.1,"speed":1}})", 23, -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":24,"method":"drive","params":{"wz":[1]}})", 24, -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":25,"method":"drive","params":{"vx":"0.1"}})", 25, -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":26,"method":"subscribe","params":{"topics":["weather"]}})", 26,
               -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":27,"method":"subscribe","params":{"topics":"telemetry"}})", 27,
               -32602);
  expect_error(client, R"({"jsonrpc":"2.0","id":28,"method":"subscribe","params":{"topic":["status"]}})", 28,
               -32602);

  const Json status = client.call("status");
  EXPECT_TRUE(status["control"]["owner"].is_null()) << "a rejected drive took control: " << status.dump();
  const auto frames = bus.collect([](const auto& f) { return is_control_frame(f); }, 200ms);
  ASSERT_FALSE(frames.empty()) << "no control frames at all";
  for (const auto& frame : frames) EXPECT_TRUE(is_zero_control_frame(frame.frame)) << to_text(frame.frame);
}

TEST_F(DaemonApi, NotificationsGetNoReply) {
  auto client = gateway().connect();
  ASSERT_TRUE(client.send_line(R"({"jsonrpc":"2.0","method":"status"})"));
  ASSERT_TRUE(client.send_line(R"({"jsonrpc":"2.0","method":"fly"})"));
  ASSERT_TRUE(client.send_line(R"({"jsonrpc":"2.0","method":"drive","params":{"vx":"fast"}})"));
  ASSERT_TRUE(client.send_line(R"({"jsonrpc":"2.0","id":30,"method":"version"})"));
  const auto next = client.next_message(2s);
  ASSERT_TRUE(next.has_value()) << "no reply to the request after three notifications";
  EXPECT_EQ((*next)["id"], 30) << "a notification was answered: " << next->dump();
  EXPECT_FALSE(client.next_message(300ms).has_value());
}

TEST_F(DaemonApi, OverlongLineClosesOnlyThatConnection) {
  CanBus bus(test_interface());
  auto bystander = gateway().connect();
  bystander.call("subscribe", {{"topics", {"telemetry"}}});
  auto offender = gateway().connect();

  std::string line = R"({"jsonrpc":"2.0","id":40,"method":"status","params":{"pad":")";
  line.append(200 * 1024, 'x');
  line += "\"}}";
  offender.send_line(line);
  ASSERT_TRUE(offender.wait_closed(3s)) << "the daemon did not close a connection that sent a 200 KiB line";
  ASSERT_EQ(offender.unread_lines().size(), 1u) << "expected exactly one error before the close";
  const Json error = Json::parse(offender.unread_lines().front());
  EXPECT_TRUE(error["error"].is_object()) << error.dump();
  EXPECT_TRUE(error["error"]["code"].is_number_integer()) << error.dump();

  EXPECT_TRUE(gateway().daemon().running());
  EXPECT_EQ(bystander.call("status")["chassis"]["online"], true);
  bystander.notifications().clear();
  EXPECT_TRUE(bystander.wait_notification("telemetry", 1s).has_value()) << "other clients must keep their telemetry";
  bus.discard_pending();
  const auto frames = bus.collect([](const auto& f) { return is_control_frame(f); }, 1000ms);
  EXPECT_GE(frames.size(), 17u) << "control frames must continue at 20 Hz";
  EXPECT_TRUE(gateway().connect().call("status").is_object()) << "new clients must be accepted";
}

TEST_F(DaemonApi, ManyClientsAreServedIndependently) {
  std::vector<RpcConnection> clients;
  for (int i = 0; i < 10; ++i) clients.push_back(gateway().connect());
  for (auto& client : clients) client.send_line(R"({"jsonrpc":"2.0","id":"v","method":"version"})");
  for (auto& client : clients) {
    const auto response = client.wait_response("v", 2s);
    ASSERT_TRUE(response.has_value());
    EXPECT_EQ((*response)["result"]["protocol"], wheeltec::kProtocolVersion);
  }
  const Json stats = clients.front().call("stats");
  EXPECT_GE(stats["clients"].get<int>(), 10) << stats.dump();
}

}  // namespace
}  // namespace integration
