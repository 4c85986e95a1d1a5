#include "serial_web.hpp"

#include "loopback_tcp.hpp"

#include <fstream>
#include <regex>
#include <stdexcept>
#include <thread>

namespace web_tests {

namespace {

std::string run_shell(const std::string& script, const std::filesystem::path& directory) {
  const auto done = integration::run_program("/bin/sh", {"-ec", script}, directory, 30s);
  if (!done.status.exited_with(0)) {
    throw std::runtime_error("openssl failed: " + done.status.describe() + "\n" + script + "\n" + done.err);
  }
  return done.out;
}

}  // namespace

TestCertificates make_test_certificates(const std::filesystem::path& directory) {
  const std::filesystem::path dir = directory / "tls";
  std::filesystem::create_directories(dir);
  TestCertificates made{dir / "ca.pem", dir / "server.pem", dir / "server.key", dir / "renewed.pem",
                        dir / "renewed.key", ""};
  run_shell(
      "cd '" + dir.string() +
          "'\n"
          "umask 077\n"
          "openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -keyout ca.key -out ca.pem -days 2 "
          "  -subj '/CN=wheeltec test CA' 2>/dev/null\n"
          "printf 'subjectAltName=IP:127.0.0.1,DNS:localhost\\n' > san.ext\n"
          "for name in server renewed; do\n"
          "  openssl req -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -keyout $name.key -out $name.csr "
          "    -subj \"/CN=$name\" 2>/dev/null\n"
          "  openssl x509 -req -in $name.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 -extfile san.ext "
          "    -out $name.pem 2>/dev/null\n"
          "done\n"
          "chmod 0644 ca.pem server.pem renewed.pem\n",
      directory);
  made.spki_sha256 = run_shell("openssl x509 -in '" + made.cert.string() +
                                   "' -pubkey -noout | openssl pkey -pubin -outform der | "
                                   "openssl dgst -sha256 -binary | base64",
                               directory);
  while (!made.spki_sha256.empty() && std::isspace(static_cast<unsigned char>(made.spki_sha256.back()))) {
    made.spki_sha256.pop_back();
  }
  return made;
}

HttpAnswer parse_answer(const std::string& raw) {
  HttpAnswer answer;
  const auto end = raw.find("\r\n\r\n");
  if (raw.rfind("HTTP/1.1 ", 0) != 0 || end == std::string::npos) {
    answer.head = raw.substr(0, 300);
    return answer;
  }
  answer.status = std::stoi(raw.substr(9, 3));
  answer.head = raw.substr(0, end);
  std::smatch length;
  std::size_t size = raw.size() - end - 4;
  if (std::regex_search(answer.head, length, std::regex("\r\nContent-Length: ([0-9]+)"))) {
    size = std::min<std::size_t>(size, std::stoull(length[1]));
  }
  answer.body = raw.substr(end + 4, size);
  answer.rest = raw.substr(end + 4 + size);
  return answer;
}

HttpAnswer http_request(int port, const std::string& method, const std::string& target, const std::string& headers,
                        const std::string& body) {
  const std::string length = body.empty() ? "" : "Content-Length: " + std::to_string(body.size()) + "\r\n";
  return parse_answer(integration::loopback_exchange(
      port, method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + headers + length +
                "Connection: close\r\n\r\n" + body));
}

std::string header_line(const HttpAnswer& answer, const std::string& name) {
  const auto at = answer.head.find("\r\n" + name + ": ");
  if (at == std::string::npos) return "";
  const auto start = at + 4 + name.size();
  return answer.head.substr(start, answer.head.find("\r\n", start) - start);
}

void SerialWebTest::SetUp() {
  SerialTest::SetUp();
  fake_->start_telemetry(20ms);
  start_daemon_ready(daemon_options());
  token_file_ = directory_->path() / "token";
  std::ofstream(token_file_) << kToken << "\n";
  std::filesystem::permissions(token_file_,
                               std::filesystem::perms::owner_read | std::filesystem::perms::owner_write);
}

void SerialWebTest::TearDown() {
  if (HasFailure()) std::cerr << web_logs();
  web_.reset();
  SerialTest::TearDown();
}

ChildProcess& SerialWebTest::start_web(int port, const std::vector<std::string>& extra) {
  std::vector<std::string> arguments{"--socket",     daemons_.front()->socket_path().string(),
                                     "--listen",     "127.0.0.1:" + std::to_string(port),
                                     "--token-file", token_file_.string(),
                                     "--page-dir",   WHEELTEC_WEB_PAGE_SOURCE};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  web_ = std::make_unique<ChildProcess>("wheeltec-web", WHEELTEC_WEB_PATH, arguments, directory_->path());
  for (int i = 0; i < 100 && !integration::loopback_accepts(port); ++i) {
    if (!web_->running()) break;
    std::this_thread::sleep_for(50ms);
  }
  if (!integration::loopback_accepts(port)) {
    throw std::runtime_error("wheeltec-web does not listen on " + std::to_string(port) + "\n" + web_logs());
  }
  return *web_;
}

nlohmann::json SerialWebTest::run_client(const std::string& mode, const std::string& url,
                                         const std::vector<std::string>& extra,
                                         const ChildProcess::Environment& environment) const {
  std::vector<std::string> arguments = {WHEELTEC_WEB_CLIENTS "/foxglove_client.cjs", mode, url};
  arguments.insert(arguments.end(), extra.begin(), extra.end());
  ChildProcess::Environment env = {{"NODE_PATH", WHEELTEC_WEB_NODE_MODULES}};
  env.insert(env.end(), environment.begin(), environment.end());
  const auto done = integration::run_program("/usr/bin/node", arguments, directory_->path(), 40s, env);
  const auto line_end = done.out.rfind('\n', done.out.size() >= 2 ? done.out.size() - 2 : 0);
  const std::string last = done.out.substr(line_end == std::string::npos ? 0 : line_end + 1);
  nlohmann::json result = nlohmann::json::parse(last, nullptr, false);
  if (result.is_discarded()) result = nlohmann::json{{"ok", false}, {"output", done.describe()}};
  result["exit"] = done.status.describe();
  return result;
}

}  // namespace web_tests
