// wheeltec::client::Connection against a scripted daemon on a Unix socket: what the
// telemetry handlers get, and that bad lines close the connection with a clear error
// instead of throwing out of the io_context.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/write.hpp>
#include <gtest/gtest.h>

#include "wheeltec/client/connection.hpp"

namespace wheeltec::client {
namespace {

using boost::asio::local::stream_protocol;

constexpr std::string_view kRecordParams =
    R"({"seq":7,"time":1763800000.123456,"stopped":false,"velocity":{"vx":0.257,"vy":0.001,"wz":0.000},)"
    R"("accel":{"x":-0.2165,"y":-0.3361,"z":9.8756},"gyro":{"x":-0.00133,"y":0.00187,"z":0.00027},)"
    R"("battery":{"voltage":22.584,"low":false},"odom":{"x":0.000000,"y":0.000000,"yaw":0.000000}})";

std::string telemetry_line(std::string_view record) {
  return std::string(R"({"jsonrpc":"2.0","method":"telemetry","params":)") + std::string(record) + "}\n";
}

// Accepts one connection, writes `lines` to it, and keeps it open; the test's io_context
// runs both ends.
class ScriptedDaemon {
 public:
  ScriptedDaemon(boost::asio::io_context& io, std::string lines)
      : path_(std::filesystem::temp_directory_path() / ("wheeltec-client-test-" + std::to_string(::getpid()) + ".sock")),
        acceptor_(io),
        peer_(io),
        lines_(std::move(lines)) {
    std::filesystem::remove(path_);
    acceptor_ = stream_protocol::acceptor(io, stream_protocol::endpoint(path_.string()));
    acceptor_.async_accept(peer_, [this](boost::system::error_code ec) {
      if (!ec) boost::asio::async_write(peer_, boost::asio::buffer(lines_), [](auto, std::size_t) {});
    });
  }
  ~ScriptedDaemon() { std::filesystem::remove(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
  stream_protocol::acceptor acceptor_;
  stream_protocol::socket peer_;
  std::string lines_;
};

struct Seen {
  std::vector<std::string> texts;
  std::vector<Telemetry> records;
  std::optional<boost::system::error_code> closed;
};

Seen run(std::string lines, bool typed, bool text) {
  boost::asio::io_context io;
  ScriptedDaemon daemon(io, std::move(lines));
  Connection connection(io.get_executor());
  Seen seen;
  if (typed) connection.on_telemetry([&](const Telemetry& record) { seen.records.push_back(record); });
  if (text) connection.on_telemetry_text([&](std::string_view record) { seen.texts.emplace_back(record); });
  connection.on_close([&](boost::system::error_code ec) { seen.closed = ec; });
  connection.async_connect(daemon.path(), [](boost::system::error_code ec) { ASSERT_FALSE(ec) << ec.message(); });
  io.run_for(std::chrono::milliseconds(300));
  return seen;
}

TEST(ClientConnectionLines, TheTextHandlerGetsTheDaemonsBytes) {
  const Seen seen = run(telemetry_line(kRecordParams) + telemetry_line(kRecordParams), false, true);
  ASSERT_EQ(seen.texts.size(), 2u);
  EXPECT_EQ(seen.texts[0], kRecordParams);
  EXPECT_FALSE(seen.closed);
}

TEST(ClientConnectionLines, BothHandlersGetTheSameRecord) {
  const Seen seen = run(telemetry_line(kRecordParams), true, true);
  ASSERT_EQ(seen.texts.size(), 1u);
  ASSERT_EQ(seen.records.size(), 1u);
  EXPECT_EQ(seen.records[0].seq, 7u);
  EXPECT_DOUBLE_EQ(seen.records[0].velocity.vx, 0.257);
  EXPECT_EQ(seen.records[0].json, Json::parse(kRecordParams));
}

TEST(ClientConnectionLines, AnotherLayoutIsParsedAndGivenAsText) {
  const Seen seen = run(R"({"method":"telemetry","params":{"seq":3},"jsonrpc":"2.0"})" "\n", false, true);
  ASSERT_EQ(seen.texts.size(), 1u);
  EXPECT_EQ(seen.texts[0], R"({"seq":3})");
}

TEST(ClientConnectionLines, ABrokenRecordClosesTheConnectionWithInvalidArgument) {
  const Seen seen = run(telemetry_line(kRecordParams) + telemetry_line(R"({"seq":8,,})") + telemetry_line(kRecordParams), true, true);
  EXPECT_EQ(seen.texts.size(), 1u);
  EXPECT_EQ(seen.records.size(), 1u);
  ASSERT_TRUE(seen.closed);
  EXPECT_EQ(*seen.closed, boost::asio::error::invalid_argument);
}

TEST(ClientConnectionLines, MistypedMembersCloseTheConnectionAndThrowNothing) {
  for (const std::string line : {R"({"jsonrpc":"2.0","method":5,"params":{}})", R"([1,2])", "not json"}) {
    const Seen seen = run(line + "\n", true, true);
    ASSERT_TRUE(seen.closed) << line;
    EXPECT_EQ(*seen.closed, boost::asio::error::invalid_argument) << line;
  }
}

TEST(ClientConnectionLines, ARecordLackingAFieldSkipsOnlyTheTypedHandler) {
  const Seen seen = run(telemetry_line(R"({"seq":9})") + telemetry_line(kRecordParams), true, true);
  EXPECT_EQ(seen.texts.size(), 2u);
  ASSERT_EQ(seen.records.size(), 1u);
  EXPECT_EQ(seen.records[0].seq, 7u);
  EXPECT_FALSE(seen.closed);
}

// The events topic (protocol 4): each EVENT object to on_event, in the daemon's key order,
// in either layout; an event that is not an object is skipped.
TEST(ClientConnectionLines, EventsGoToTheEventHandlerAsTheyCame) {
  boost::asio::io_context io;
  const std::string drive = R"({"time":1795816069.675096,"event":"drive","client":5,"vx":1.000,"vy":0.000,"wz":0.500,"clamped":true})";
  ScriptedDaemon daemon(io, R"({"jsonrpc":"2.0","method":"event","params":)" + drive + "}\n" +
                                R"({"jsonrpc":"2.0","method":"event","params":3})" "\n" +
                                R"({"params":{"time":1.5,"event":"mark","client":6,"text":"x"},"method":"event","jsonrpc":"2.0"})" "\n");
  Connection connection(io.get_executor());
  std::vector<Json> events;
  connection.on_event([&](const Json& event) { events.push_back(event); });
  bool closed = false;
  connection.on_close([&](boost::system::error_code) { closed = true; });
  connection.async_connect(daemon.path(), [](boost::system::error_code ec) { ASSERT_FALSE(ec) << ec.message(); });
  io.run_for(std::chrono::milliseconds(300));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0], Json::parse(drive));
  EXPECT_EQ(events[0].begin().key(), "time") << "the daemon's key order";
  EXPECT_EQ(events[1]["text"], "x");
  EXPECT_FALSE(closed);
}

}  // namespace
}  // namespace wheeltec::client
