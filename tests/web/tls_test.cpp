// wheeltec-web over TLS (spec section 6, TLS): npm's Foxglove client over wss:// with a test
// CA made by openssl, under every rule of the plain server; plain HTTP, garbage, an old
// protocol and a stalled handshake on the TLS port cost only their connection, and a
// thousand of them only a few log lines; a key file others can read is refused; SIGHUP loads
// a renewed pair for new connections and keeps open viewers. The robot is on the serial link
// (serial_web.hpp), natively.

#include <gtest/gtest.h>

#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <thread>

#include "loopback_tcp.hpp"
#include "serial_web.hpp"

namespace web_tests {
namespace {

constexpr int kTlsPort = 18091;

std::string exchange(const std::string& bytes) { return integration::loopback_exchange(kTlsPort, bytes); }

class WebTls : public SerialWebTest {
 protected:
  void SetUp() override {
    SerialWebTest::SetUp();
    if (HasFatalFailure()) return;
    certificates_ = make_test_certificates(directory_->path());
  }

  void start_tls_web(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> arguments{"--tls-cert", certificates_.cert.string(), "--tls-key",
                                       certificates_.key.string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    start_web(kTlsPort, arguments);
  }
  std::string wss_url() const { return "wss://127.0.0.1:" + std::to_string(kTlsPort); }
  ChildProcess::Environment trusting_the_ca() const { return {{"NODE_EXTRA_CA_CERTS", certificates_.ca.string()}}; }
  nlohmann::json client(const std::string& mode, const std::vector<std::string>& extra = {}) const {
    return run_client(mode, wss_url(), extra, trusting_the_ca());
  }
  nlohmann::json probe(const std::vector<std::string>& arguments) const {
    std::vector<std::string> command{WHEELTEC_WEB_CLIENTS "/tls_probe.cjs"};
    command.insert(command.end(), arguments.begin(), arguments.end());
    const auto done = integration::run_program("/usr/bin/node", command, directory_->path(), 20s);
    nlohmann::json result = nlohmann::json::parse(done.out, nullptr, false);
    if (result.is_discarded()) result = nlohmann::json{{"ok", false}, {"output", done.describe()}};
    return result;
  }
  std::string peer_subject() const {
    const nlohmann::json peer = probe({"peer", std::to_string(kTlsPort), certificates_.ca.string()});
    EXPECT_EQ(peer["ok"], true) << peer.dump();
    return peer.value("subject", "");
  }

  TestCertificates certificates_;
};

TEST_F(WebTls, FoxgloveOverWssSeesEveryChannelDrivesAndMeetsTheSameRules) {
  start_tls_web({"--allow-origin", "https://app.foxglove.dev"});
  const nlohmann::json peer = probe({"peer", std::to_string(kTlsPort), certificates_.ca.string()});
  EXPECT_EQ(peer["ok"], true) << peer.dump();
  EXPECT_TRUE(peer["protocol"] == "TLSv1.3" || peer["protocol"] == "TLSv1.2") << peer.dump();

  const nlohmann::json live = client("live");
  EXPECT_EQ(live["ok"], true) << live.dump(2);
  EXPECT_EQ(live["topics"],
            nlohmann::json({"/wheeltec/telemetry", "/wheeltec/status", "/wheeltec/odom", "/wheeltec/imu"}));

  const std::size_t before = fake_->command_count();
  const nlohmann::json drive = client("drive", {kToken});
  EXPECT_EQ(drive["ok"], true) << drive.dump(2);
  const auto left = SteadyClock::now();
  std::size_t moving_index = 0;
  const auto moving = fake_->wait_command([](const CommandSeen& f) { return !f.zero(); }, 1s, before, &moving_index);
  ASSERT_TRUE(moving) << "no command frame with motion from a wss:// drive\n" << logs() << web_logs();
  EXPECT_EQ(moving->x, 300) << moving->text();  // mm/s
  EXPECT_EQ(moving->z, 500) << moving->text();  // 0.001 rad/s
  const auto zero = fake_->wait_command([](const CommandSeen& f) { return f.zero(); }, 2s, moving_index);
  ASSERT_TRUE(zero) << "the robot was not stopped after the wss:// client left\n" << logs();
  EXPECT_LT(serial_tests::seconds_between(left, zero->time), 0.6);

  for (const char* mode : {"read-only", "origins", "malformed", "oversized"}) {
    const nlohmann::json result = client(mode);
    EXPECT_EQ(result["ok"], true) << mode << ": " << result.dump(2);
  }
  const nlohmann::json second = client("second-driver", {kToken});
  EXPECT_EQ(second["ok"], true) << second.dump(2);
  ASSERT_TRUE(web_->running()) << web_logs();
}

TEST_F(WebTls, PlainHttpGarbageOldProtocolsAndStalledHandshakesCostOnlyTheirConnection) {
  start_tls_web();
  // A client that connects and never says anything, held open through the rest.
  const int stalled = integration::connect_loopback(kTlsPort);
  ASSERT_GE(stalled, 0);
  const auto stalled_since = SteadyClock::now();

  const std::string plain = exchange("GET /api/status HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n");
  EXPECT_NE(plain.find("HTTP/1.1 400"), std::string::npos) << plain;
  EXPECT_NE(plain.find("use https://"), std::string::npos) << plain;
  // A TLS record that starts as a ClientHello and goes on as junk: the handshake fails and
  // the connection is closed.
  const std::string garbage = exchange(std::string("\x16\x03\x01\x00\x40\x01\x00\x00\x3c", 9) + std::string(60, '\x5a'));
  EXPECT_EQ(garbage.find("HTTP/"), std::string::npos) << garbage;
  const nlohmann::json old = probe({"old", std::to_string(kTlsPort)});
  EXPECT_EQ(old["ok"], true) << "a TLS 1.1 client was accepted: " << old.dump();

  // Meanwhile a Foxglove client over wss:// is served as usual.
  const nlohmann::json live = client("live");
  EXPECT_EQ(live["ok"], true) << live.dump(2) << web_logs();

  // The silent client is dropped at the handshake's deadline (10 s), not held forever.
  timeval tv{15, 0};
  ::setsockopt(stalled, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  char byte = 0;
  const ssize_t n = ::read(stalled, &byte, 1);
  const double held_s = serial_tests::seconds_between(stalled_since, SteadyClock::now());
  ::close(stalled);
  EXPECT_EQ(n, 0) << "the stalled connection was not closed by the server";
  EXPECT_GT(held_s, 8.0);
  EXPECT_LT(held_s, 13.0);
  std::printf("[ figure ] a silent client dropped after %.1f s\n", held_s);

  // The server closes a timed-out socket before it logs why.
  for (int i = 0; i < 40 && web_->standard_error().find("stalled before") == std::string::npos; ++i) {
    std::this_thread::sleep_for(50ms);
  }
  const std::string log = web_->standard_error();
  EXPECT_NE(log.find("sent plain HTTP to the TLS port"), std::string::npos) << log;
  EXPECT_NE(log.find("failed in the TLS handshake"), std::string::npos) << log;
  EXPECT_NE(log.find("unsupported protocol"), std::string::npos) << log;
  EXPECT_NE(log.find("stalled before a TLS handshake"), std::string::npos) << log;
  ASSERT_TRUE(web_->running()) << web_logs();
}

// What a scanner costs the journal: the failures of one kind are logged 5 at once, then one
// every 5 s that says how many were suppressed before it (kPeerLogBudget).
TEST_F(WebTls, AThousandBadHandshakesLeaveAFewLinesAndACount) {
  start_tls_web();
  const std::string junk = std::string("\x16\x03\x01\x00\x40\x01\x00\x00\x3c", 9) + std::string(60, '\x5a');
  constexpr int kFlood = 1000;
  const auto flood_started = SteadyClock::now();
  for (int i = 0; i < kFlood; ++i) ASSERT_EQ(exchange(junk).find("HTTP/"), std::string::npos);
  const double flood_s = serial_tests::seconds_between(flood_started, SteadyClock::now());
  std::printf("[ figure ] %d bad handshakes in %.1f s\n", kFlood, flood_s);

  // One more once the budget has a line again: that line carries the count of the rest.
  std::this_thread::sleep_for(5200ms);
  exchange(junk);
  std::size_t lines = 0;
  std::uint64_t suppressed = 0;
  for (int attempt = 0; attempt < 40; ++attempt) {
    const std::string log = web_->standard_error();
    lines = 0;
    suppressed = 0;
    for (std::size_t at = log.find("failed in the TLS handshake"); at != std::string::npos;
         at = log.find("failed in the TLS handshake", at + 1)) {
      ++lines;
      const std::string line = log.substr(at, log.find('\n', at) - at);
      if (line.ends_with(" more suppressed)")) suppressed += std::stoull(line.substr(line.rfind('(') + 1));
    }
    if (lines + suppressed >= kFlood + 1) break;
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_LE(lines, 5 + 1 + static_cast<std::size_t>(flood_s / 5.0)) << web_logs();
  EXPECT_EQ(lines + suppressed, static_cast<std::uint64_t>(kFlood + 1))
      << "every failed handshake is a line or in a count\n" << web_logs();
  ASSERT_TRUE(web_->running()) << web_logs();
}

TEST_F(WebTls, AKeyOthersCanReadAndAHalfPairAreRefusedWithExit2) {
  std::filesystem::permissions(certificates_.key, std::filesystem::perms::others_read, std::filesystem::perm_options::add);
  const auto open_key = integration::run_program(
      WHEELTEC_WEB_PATH,
      {"--socket", "/nonexistent.sock", "--listen", "127.0.0.1:" + std::to_string(kTlsPort), "--tls-cert",
       certificates_.cert.string(), "--tls-key", certificates_.key.string()},
      directory_->path(), 10s);
  EXPECT_TRUE(open_key.status.exited_with(2)) << open_key.describe();
  EXPECT_NE(open_key.err.find(certificates_.key.string()), std::string::npos) << open_key.err;
  EXPECT_NE(open_key.err.find("readable or writable by others"), std::string::npos) << open_key.err;
  EXPECT_EQ(std::count(open_key.err.begin(), open_key.err.end(), '\n'), 1) << open_key.err;

  const auto half = integration::run_program(
      WHEELTEC_WEB_PATH, {"--socket", "/nonexistent.sock", "--tls-cert", certificates_.cert.string()},
      directory_->path(), 10s);
  EXPECT_TRUE(half.status.exited_with(2)) << half.describe();
  EXPECT_NE(half.err.find("go together"), std::string::npos) << half.err;

  const auto wrong_key = integration::run_program(
      WHEELTEC_WEB_PATH,
      {"--socket", "/nonexistent.sock", "--tls-cert", certificates_.cert.string(), "--tls-key",
       certificates_.key2.string()},
      directory_->path(), 10s);
  EXPECT_TRUE(wrong_key.status.exited_with(2)) << wrong_key.describe();
  EXPECT_NE(wrong_key.err.find("does not belong to the certificate"), std::string::npos) << wrong_key.err;
}

TEST_F(WebTls, SighupLoadsARenewedPairForNewConnectionsAndKeepsOpenViewers) {
  start_tls_web();
  EXPECT_EQ(peer_subject(), "server");
  ChildProcess watcher("watcher", "/usr/bin/node", {WHEELTEC_WEB_CLIENTS "/foxglove_client.cjs", "watch", wss_url(), "6"},
                       directory_->path(),
                       {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}, {"NODE_EXTRA_CA_CERTS", certificates_.ca.string()}});
  std::this_thread::sleep_for(1500ms);  // the watcher is connected and receiving

  // Renewal: new files in place, then SIGHUP.
  std::filesystem::copy_file(certificates_.cert2, certificates_.cert, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(certificates_.key2, certificates_.key, std::filesystem::copy_options::overwrite_existing);
  web_->send_signal(SIGHUP);
  std::string subject;
  for (int i = 0; i < 50 && (subject = peer_subject()) != "renewed"; ++i) std::this_thread::sleep_for(100ms);
  EXPECT_EQ(subject, "renewed") << web_logs();

  // A pair that does not load (a key of another certificate) is logged and the renewed one kept.
  const auto other_key = directory_->path() / "tls" / "other.key";
  integration::run_program(
      "/bin/sh", {"-ec", "umask 077; openssl genpkey -algorithm EC -pkeyopt ec_paramgen_curve:P-256 -out '" +
                             other_key.string() + "'"},
      directory_->path(), 10s);
  std::filesystem::copy_file(other_key, certificates_.key, std::filesystem::copy_options::overwrite_existing);
  web_->send_signal(SIGHUP);
  for (int i = 0; i < 50 && web_->standard_error().find("stays in use") == std::string::npos; ++i) {
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_NE(web_->standard_error().find("does not belong to the certificate"), std::string::npos) << web_logs();
  EXPECT_EQ(peer_subject(), "renewed");

  const auto watched = watcher.wait_for_exit(20s);
  ASSERT_TRUE(watched) << watcher.output_report();
  EXPECT_TRUE(watched->exited_with(0)) << watcher.output_report() << web_logs();
  ASSERT_TRUE(web_->running()) << web_logs();
}

}  // namespace
}  // namespace web_tests
