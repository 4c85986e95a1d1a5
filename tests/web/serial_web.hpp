#pragma once

// wheeltec-web in front of wheeltecd on the serial link, natively: the serial suite's fake
// controller on a pseudo-terminal (50 records a second, every command frame recorded with its
// arrival time), the daemon on it, and wheeltec-web started by each test with its own flags.
// For the suites that need no vcan: the page in Chromium and TLS.

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "serial_daemon.hpp"

namespace web_tests {

using namespace std::chrono_literals;
using integration::ChildProcess;
using serial_tests::CommandSeen;
using serial_tests::SteadyClock;

inline constexpr const char* kToken = "s3cret-token";

// A test CA and server certificates it signed for 127.0.0.1 and localhost, made by openssl.
struct TestCertificates {
  std::filesystem::path ca;          // the CA's certificate: what clients trust
  std::filesystem::path cert, key;   // the server's pair (key 0600)
  std::filesystem::path cert2, key2; // a second pair from the same CA, for a renewal
  // base64 of SHA-256 over the pair's public key, as Chromium's --ignore-certificate-errors-spki-list wants.
  std::string spki_sha256;
};
TestCertificates make_test_certificates(const std::filesystem::path& directory);

// An HTTP response as the tests read it off the wire.
struct HttpAnswer {
  int status = 0;
  std::string head;  // status line and headers
  std::string body;
  std::string rest;  // what followed the body (the next response on a kept-alive connection)
};

// One response off the front of `raw`, its body as long as Content-Length says.
HttpAnswer parse_answer(const std::string& raw);
// One request to 127.0.0.1:port on a connection of its own; `headers` each end in CR LF.
// A `body` is sent with its Content-Length.
HttpAnswer http_request(int port, const std::string& method, const std::string& target,
                        const std::string& headers = "", const std::string& body = "");
// The value of header `name` in `answer`, "" when it has none.
std::string header_line(const HttpAnswer& answer, const std::string& name);

class SerialWebTest : public serial_tests::SerialTest {
 protected:
  void SetUp() override;
  // The daemon SetUp starts (a suite may want another chassis).
  virtual serial_tests::DaemonOptions daemon_options() const { return {}; }
  void TearDown() override;

  // wheeltec-web on 127.0.0.1:port with the token file and the page's sources, plus `extra`
  // flags; waits until it accepts connections.
  ChildProcess& start_web(int port, const std::vector<std::string>& extra = {});
  // Runs tests/web/clients/foxglove_client.cjs MODE URL [TOKEN]; its last JSON line (with "exit").
  nlohmann::json run_client(const std::string& mode, const std::string& url, const std::vector<std::string>& extra = {},
                            const ChildProcess::Environment& environment = {}) const;
  std::string web_logs() const { return web_ ? web_->output_report() : std::string(); }

  std::filesystem::path token_file_;
  std::unique_ptr<ChildProcess> web_;
};

}  // namespace web_tests
