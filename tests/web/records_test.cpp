// The recorder's files in wheeltec-web (docs/web.md, "Recordings"): a record directory made
// up by the test (recordings of given contents, a .part, foreign files, a symlink out of the
// directory, a directory under a recording's name), served over real HTTP and HTTPS: the
// list newest first with no .part, foreign file or symlink; downloads of exactly the bytes;
// 404 for everything else, path tricks included; the access rules of /api/status; a client
// that stops reading a large download holds up nobody and is cut off; the page lists them.
// The robot is on the serial link (serial_web.hpp), natively.

#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <thread>

#include "loopback_tcp.hpp"
#include "serial_web.hpp"
#include "wheeltec/mcap/writer.hpp"

namespace web_tests {
namespace {

constexpr int kRecordsPort = 18092;  // web.Page's instance listens on 18090, web.Tls's on 18091

const std::string kDeadman = "20261127T153012Z-deadman.mcap";
const std::string kContinuous = "20261127T160000Z-continuous.mcap";
const std::string kBatteryLow = "20261126T080000Z-battery-low.mcap";
const std::string kPart = "20261127T170000Z-mark.mcap.part";  // the newest, still being written
const std::string kSymlink = "20261127T190000Z-halted.mcap";  // -> ../secret.txt
const std::string kDirectory = "20261127T200000Z-reboot.mcap";

// Bytes that no text handling would leave alone: NULs, CR LF, every byte value.
std::string made_up_bytes(std::size_t size, unsigned seed) {
  std::mt19937 random(seed);
  std::string bytes(size, '\0');
  for (char& byte : bytes) byte = static_cast<char>(random());
  if (size >= 4) bytes.replace(0, 4, std::string("\0\r\n\x89", 4));
  return bytes;
}

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// One request on a connection of its own; `headers` each end in CR LF.
HttpAnswer http_request(const std::string& method, const std::string& target, const std::string& headers = "") {
  return web_tests::http_request(kRecordsPort, method, target, headers);
}
HttpAnswer http_get(const std::string& target, const std::string& headers = "") {
  return http_request("GET", target, headers);
}

class WebRecords : public SerialWebTest {
 protected:
  void SetUp() override {
    SerialWebTest::SetUp();
    if (HasFatalFailure()) return;
    records_ = directory_->path() / "records";
    std::filesystem::create_directories(records_);
    contents_[kDeadman] = made_up_bytes(3'000'001, 1);  // hundreds of 4 KiB pieces
    contents_[kContinuous] = made_up_bytes(1000, 2);
    contents_[kBatteryLow] = "";  // an empty file is a file too
    for (const auto& [name, bytes] : contents_) write_file(records_ / name, bytes);
    write_file(records_ / kPart, "half");
    write_file(records_ / "notes.txt", "not a recording");
    write_file(records_ / "20261127T180000Z-unknown.mcap", "an unknown trigger");
    write_file(directory_->path() / "secret.txt", "outside the record directory");
    std::filesystem::create_symlink("../secret.txt", records_ / kSymlink);
    std::filesystem::create_directory(records_ / kDirectory);
  }

  void start(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> arguments{"--record-dir", records_.string()};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    start_web(kRecordsPort, arguments);
  }

  // curl over https:// trusting the test CA: the status, and the body in `out`.
  int curl(const TestCertificates& certificates, const std::string& target, const std::filesystem::path& out,
           const std::vector<std::string>& extra = {}) const {
    std::vector<std::string> arguments{"-sS", "--cacert", certificates.ca.string(), "-o", out.string(),
                                       "-w", "%{http_code}"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    arguments.push_back("https://127.0.0.1:" + std::to_string(kRecordsPort) + target);
    const auto done = integration::run_program("/usr/bin/curl", arguments, directory_->path(), 30s);
    EXPECT_TRUE(done.status.exited_with(0)) << done.describe();
    return std::atoi(done.out.c_str());
  }

  std::filesystem::path records_;
  std::map<std::string, std::string> contents_;
};

nlohmann::json expected_list() {
  return nlohmann::json::parse(R"({"records": [
    {"name": "20261127T160000Z-continuous.mcap", "trigger": "continuous", "time": 1795795200, "bytes": 1000},
    {"name": "20261127T153012Z-deadman.mcap", "trigger": "deadman", "time": 1795793412, "bytes": 3000001},
    {"name": "20261126T080000Z-battery-low.mcap", "trigger": "battery-low", "time": 1795680000, "bytes": 0}]})");
}

TEST_F(WebRecords, ListsWholeRecordingsNewestFirstAndServesExactlyTheirBytes) {
  start();
  const HttpAnswer list = http_get("/api/records");
  ASSERT_EQ(list.status, 200) << list.head << list.body;
  EXPECT_EQ(header_line(list, "Content-Type"), "application/json");
  EXPECT_EQ(nlohmann::json::parse(list.body, nullptr, false), expected_list()) << list.body;

  for (const auto& [name, bytes] : contents_) {
    const HttpAnswer file = http_get("/api/records/" + name);
    ASSERT_EQ(file.status, 200) << name << "\n" << file.head;
    EXPECT_EQ(header_line(file, "Content-Type"), "application/octet-stream");
    EXPECT_EQ(header_line(file, "Content-Disposition"), "attachment; filename=\"" + name + "\"");
    EXPECT_EQ(header_line(file, "Content-Length"), std::to_string(bytes.size()));
    EXPECT_EQ(file.body.size(), bytes.size()) << name;
    EXPECT_TRUE(file.body == bytes) << name << ": other bytes than the file's";
  }

  // Kept alive: a download, then the list on the same connection.
  const HttpAnswer first = parse_answer(integration::loopback_exchange(
      kRecordsPort, "GET /api/records/" + kContinuous + " HTTP/1.1\r\nHost: x\r\n\r\n"
             "GET /api/records?fresh=1 HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
  EXPECT_EQ(first.status, 200) << first.head;
  EXPECT_TRUE(first.body == contents_[kContinuous]);
  const HttpAnswer second = parse_answer(first.rest);
  EXPECT_EQ(second.status, 200) << second.head;
  EXPECT_EQ(nlohmann::json::parse(second.body, nullptr, false), expected_list()) << second.body;
  ASSERT_TRUE(web_->running()) << web_logs();
}

TEST_F(WebRecords, EverythingButAWholeRecordingIs404AndOtherMethods405) {
  start();
  for (const std::string& target :
       {"/api/records/" + kPart, "/api/records/" + kSymlink, "/api/records/" + kDirectory,
        std::string("/api/records/notes.txt"), std::string("/api/records/20261127T180000Z-unknown.mcap"),
        std::string("/api/records/20261127T210000Z-deadman.mcap"),  // a fine name, no such file
        std::string("/api/records/"), std::string("/api/records/../secret.txt"),
        std::string("/api/records/..%2Fsecret.txt"), std::string("/api/records/%2E%2E%2Fsecret.txt"),
        std::string("/api/records/..%2F..%2Frecords%2F") + kDeadman, "/api/records/%32" + kDeadman.substr(1),
        "/api/records/" + kDeadman + "/", "/api/records/" + kDeadman + "%00", "/api/records//" + kDeadman,
        "/api/records/x/../" + kDeadman, "/api/records/./" + kDeadman}) {
    const HttpAnswer answer = http_get(target);
    EXPECT_EQ(answer.status, 404) << target << "\n" << answer.head << "\n" << answer.body.substr(0, 200);
    EXPECT_EQ(answer.body.find("outside the record directory"), std::string::npos) << target;
  }
  const HttpAnswer part = http_get("/api/records/" + kPart);
  EXPECT_EQ(part.body, "no such recording: " + kPart + "\n");

  const HttpAnswer post = http_request("POST", "/api/records", "Content-Length: 0\r\n");
  EXPECT_EQ(post.status, 405) << post.head;
  EXPECT_EQ(header_line(post, "Allow"), "GET");
  EXPECT_EQ(post.body, "/api/records takes GET\n");
  const HttpAnswer remove = http_request("DELETE", "/api/records/" + kDeadman);
  EXPECT_EQ(remove.status, 405) << remove.head;
  EXPECT_TRUE(std::filesystem::exists(records_ / kDeadman));
  const HttpAnswer head = http_request("HEAD", "/api/records");
  EXPECT_EQ(head.status, 405) << head.head;  // as /api/status: the API takes its one method
  ASSERT_TRUE(web_->running()) << web_logs();
}

// The recordings are read under the rules of /api/status (docs/web.md, Security): whatever
// a token, a wrong one or a foreign Origin makes of /api/status, it makes of them.
TEST_F(WebRecords, TheAccessRulesAreThoseOfApiStatus) {
  start();
  for (const std::string& headers :
       {std::string(), std::string("Authorization: Bearer ") + kToken + "\r\n",
        std::string("Authorization: Bearer wrong\r\n"), std::string("Origin: http://evil.example\r\n")}) {
    for (const std::string& query : {std::string(), std::string("?token=wrong"), std::string("?token=") + kToken}) {
      const int status = http_get("/api/status" + query, headers).status;
      EXPECT_EQ(http_get("/api/records" + query, headers).status, status) << headers << query;
      EXPECT_EQ(http_get("/api/records/" + kDeadman + query, headers).status, status) << headers << query;
    }
  }
  // Today's rule: reading needs no token (the read-only view); the token is for driving.
  EXPECT_EQ(http_get("/api/status").status, 200);
}

TEST_F(WebRecords, AMissingDirectoryIsAnEmptyList) {
  records_ = directory_->path() / "not-there";
  start();
  const HttpAnswer list = http_get("/api/records");
  ASSERT_EQ(list.status, 200) << list.head << list.body;
  EXPECT_EQ(nlohmann::json::parse(list.body, nullptr, false), nlohmann::json::parse(R"({"records": []})"));
  EXPECT_EQ(http_get("/api/records/" + kDeadman).status, 404);
}

// A client that asks for a large file and stops reading holds nobody up: the list, the
// status and another download are served meanwhile, and it is cut off once it has taken
// nothing for 30 s (one piece's deadline), not held forever.
TEST_F(WebRecords, AClientThatStopsReadingABigDownloadHoldsUpNobody) {
  const std::string big = "20261127T150000Z-offline.mcap";
  constexpr std::size_t kBig = 64u << 20;
  write_file(records_ / big, std::string(kBig, 'r'));
  start();
  // A small receive buffer, set before connecting so that the window is scaled for it.
  const int slow = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(slow, 0);
  const int small_buffer = 4096;
  ::setsockopt(slow, SOL_SOCKET, SO_RCVBUF, &small_buffer, sizeof small_buffer);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(kRecordsPort);
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(slow, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  const std::string request = "GET /api/records/" + big + " HTTP/1.1\r\nHost: x\r\n\r\n";
  ASSERT_EQ(::write(slow, request.data(), request.size()), static_cast<ssize_t>(request.size()));
  const auto asked = SteadyClock::now();
  std::this_thread::sleep_for(500ms);

  const auto before = SteadyClock::now();
  EXPECT_EQ(http_get("/api/records").status, 200);
  EXPECT_EQ(http_get("/api/status").status, 200);
  const HttpAnswer other = http_get("/api/records/" + kDeadman);
  EXPECT_TRUE(other.body == contents_[kDeadman]);
  EXPECT_LT(serial_tests::seconds_between(before, SteadyClock::now()), 2.0);

  // Not read for 35 s: the server gave up on it at its deadline, short of the whole file.
  std::this_thread::sleep_for(35s - (SteadyClock::now() - asked));
  timeval tv{5, 0};
  ::setsockopt(slow, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::size_t received = 0;
  char buffer[65536];
  bool closed = false;
  for (ssize_t n; (n = ::read(slow, buffer, sizeof buffer)) >= 0;) {
    if (n == 0) {
      closed = true;
      break;
    }
    received += static_cast<std::size_t>(n);
  }
  ::close(slow);
  EXPECT_TRUE(closed) << "the stalled download was not closed";
  EXPECT_LT(received, kBig) << "the whole file arrived though nothing read it for 35 s";
  std::printf("[ figure ] a client that stopped reading got %zu of %zu bytes before it was cut off\n", received, kBig);
  ASSERT_TRUE(web_->running()) << web_logs();
}

TEST_F(WebRecords, OverTlsTheListAndTheDownloadsAreTheSame) {
  const TestCertificates certificates = make_test_certificates(directory_->path());
  start({"--tls-cert", certificates.cert.string(), "--tls-key", certificates.key.string()});
  const auto out = directory_->path() / "download";
  ASSERT_EQ(curl(certificates, "/api/records", out), 200);
  std::ifstream list_file(out);
  EXPECT_EQ(nlohmann::json::parse(list_file, nullptr, false), expected_list());
  for (const std::string& name : {kDeadman, kContinuous}) {
    ASSERT_EQ(curl(certificates, "/api/records/" + name, out), 200) << name;
    std::ifstream in(out, std::ios::binary);
    const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    EXPECT_EQ(bytes.size(), contents_[name].size()) << name;
    EXPECT_TRUE(bytes == contents_[name]) << name << ": other bytes than the file's";
  }
  EXPECT_EQ(curl(certificates, "/api/records/" + kPart, out), 404);
  EXPECT_EQ(curl(certificates, "/api/records/../secret.txt", out, {"--path-as-is"}), 404);
  EXPECT_EQ(curl(certificates, "/api/records/" + kSymlink, out), 404);
  ASSERT_TRUE(web_->running()) << web_logs();
}

// The page's Recordings table, as headless Chromium renders it once the page has fetched
// the list: newest first, each a download link.
TEST_F(WebRecords, ThePageListsThemWithDownloadLinks) {
  start();
  const auto home = directory_->path() / "chromium-home";
  std::filesystem::create_directories(home);
  const auto done = integration::run_program(
      "/usr/bin/chromium",
      {"--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-background-networking",
       "--user-data-dir=" + (directory_->path() / "chromium-profile").string(), "--virtual-time-budget=5000",
       "--dump-dom", "http://127.0.0.1:" + std::to_string(kRecordsPort) + "/"},
      directory_->path(), 60s, {{"HOME", home.string()}});
  ASSERT_TRUE(done.status.exited_with(0)) << done.describe();
  std::smatch table;
  ASSERT_TRUE(std::regex_search(done.out, table, std::regex("<table id=\"records\">(.*?)</table>")))
      << done.out.substr(0, 3000);
  const std::string rows = table[1];
  std::vector<std::string> links;
  const std::regex link("<a href=\"/api/records/([^\"]+)\" download=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(rows.begin(), rows.end(), link); it != std::sregex_iterator(); ++it) {
    links.push_back((*it)[1]);
    EXPECT_EQ((*it)[1], (*it)[2]);
  }
  EXPECT_EQ(links, (std::vector<std::string>{kContinuous, kDeadman, kBatteryLow})) << rows;
  EXPECT_NE(rows.find("<td>deadman</td><td>2.9 MB</td>"), std::string::npos) << rows;
  EXPECT_NE(rows.find("<td>battery-low</td><td>0 B</td>"), std::string::npos) << rows;
}

// Range on a download (spec section 14): one range is 206 with its bytes and Content-Range,
// a range outside the file 416, several ranges or nonsense the whole file.
TEST_F(WebRecords, ADownloadHonoursOneByteRange) {
  start();
  const std::string& bytes = contents_[kDeadman];
  const std::string target = "/api/records/" + kDeadman;
  const HttpAnswer whole = http_get(target);
  EXPECT_EQ(header_line(whole, "Accept-Ranges"), "bytes");
  const struct {
    std::string range;
    std::size_t first, size;
  } cases[] = {{"bytes=0-99", 0, 100},
               {"bytes=2999000-", 2999000, 1001},
               {"bytes=-10", bytes.size() - 10, 10},
               {"bytes=1000000-1999999", 1000000, 1000000},
               {"bytes=2999990-9999999", 2999990, 11}};
  for (const auto& c : cases) {
    const HttpAnswer part = http_get(target, "Range: " + c.range + "\r\n");
    ASSERT_EQ(part.status, 206) << c.range << "\n" << part.head;
    EXPECT_EQ(header_line(part, "Content-Range"), "bytes " + std::to_string(c.first) + "-" +
                                                      std::to_string(c.first + c.size - 1) + "/" +
                                                      std::to_string(bytes.size()));
    EXPECT_EQ(header_line(part, "Content-Length"), std::to_string(c.size));
    EXPECT_TRUE(part.body == bytes.substr(c.first, c.size)) << c.range;
  }
  for (const std::string range : {"bytes=3000001-", "bytes=9999999-99999999", "bytes=-0"}) {
    const HttpAnswer outside = http_get(target, "Range: " + range + "\r\n");
    EXPECT_EQ(outside.status, 416) << range << "\n" << outside.head;
    EXPECT_EQ(header_line(outside, "Content-Range"), "bytes */3000001") << range;
  }
  const HttpAnswer empty = http_get("/api/records/" + kBatteryLow, "Range: bytes=0-\r\n");
  EXPECT_EQ(empty.status, 416) << empty.head;
  for (const std::string range : {"bytes=0-1,5-9", "lines=1-2", "bytes=z-"}) {
    const HttpAnswer all = http_get(target, "Range: " + range + "\r\n");
    EXPECT_EQ(all.status, 200) << range;
    EXPECT_EQ(all.body.size(), bytes.size()) << range;
  }
  // Kept alive across a 206 and a 416.
  const HttpAnswer first = parse_answer(integration::loopback_exchange(
      kRecordsPort, "GET " + target + " HTTP/1.1\r\nHost: x\r\nRange: bytes=5-9\r\n\r\n"
                    "GET " + target + " HTTP/1.1\r\nHost: x\r\nRange: bytes=5000000-\r\n\r\n"
                    "GET /api/records HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n"));
  EXPECT_EQ(first.status, 206);
  EXPECT_TRUE(first.body == bytes.substr(5, 5));
  const HttpAnswer second = parse_answer(first.rest);
  EXPECT_EQ(second.status, 416) << second.head;
  EXPECT_EQ(parse_answer(second.rest).status, 200);
  ASSERT_TRUE(web_->running()) << web_logs();
}

// A recorder-shaped file (the project's MCAP writer, the recorder's channels and metadata).
std::string recorder_shaped_file() {
  using wheeltec::mcap::text_bytes;
  wheeltec::mcap::Registry registry;
  const auto schema = registry.add_schema("wheeltec.Telemetry", "jsonschema", text_bytes("{}"));
  const auto telemetry = registry.add_channel(schema, "/telemetry", "json");
  const auto status = registry.add_channel(schema, "/status", "json");
  const auto events = registry.add_channel(schema, "/events", "json");
  std::string out;
  wheeltec::mcap::Writer writer(
      [&out](wheeltec::mcap::ByteView bytes) { out.append(reinterpret_cast<const char*>(bytes.data()), bytes.size()); },
      registry, {.library = "wheeltec-record 0.1.0", .chunk_size = 4096});
  for (int i = 0; i < 200; ++i) {
    const std::uint64_t t = 1'795'793'412'000'000'000ull + static_cast<std::uint64_t>(i) * 50'000'000ull;
    writer.write_message(telemetry, t, t, text_bytes(R"({"seq":)" + std::to_string(i) + "}"));
  }
  writer.write_message(status, 1'795'793'412'000'000'000ull, 1'795'793'412'000'000'000ull, text_bytes(R"({"s":1})"));
  writer.write_message(events, 1'795'793'415'000'000'000ull, 1'795'793'415'000'000'000ull,
                       text_bytes(R"({"time":1795793415.0,"event":"deadman","client":3})"));
  writer.write_metadata("wheeltec", {{"version", "0.1.0"}, {"triggers", R"([{"trigger":"deadman","time":1795793415.0}])"}});
  writer.finish();
  return out;
}

TEST_F(WebRecords, MessagesOfARecordingAsJsonAndWhatCannotBeReadAs422) {
  const std::string good = "20261128T100000Z-deadman.mcap";
  const std::string damaged = "20261128T110000Z-mark.mcap";
  const std::string file = recorder_shaped_file();
  write_file(records_ / good, file);
  std::string broken = file;
  broken[broken.size() / 2] ^= 0x40;
  write_file(records_ / damaged, broken);
  start();

  const HttpAnswer answer = http_get("/api/records/" + good + "/messages");
  ASSERT_EQ(answer.status, 200) << answer.head << answer.body.substr(0, 300);
  EXPECT_EQ(header_line(answer, "Content-Type"), "application/json");
  const nlohmann::json json = nlohmann::json::parse(answer.body, nullptr, false);
  ASSERT_TRUE(json.is_object()) << answer.body.substr(0, 300);
  EXPECT_EQ(json["name"], good);
  EXPECT_EQ(json["metadata"]["triggers"], R"([{"trigger":"deadman","time":1795793415.0}])");
  ASSERT_EQ(json["telemetry"].size(), 200u);
  EXPECT_EQ(json["telemetry"][199]["seq"], 199);
  EXPECT_EQ(json["status"], nlohmann::json::parse(R"([{"s":1}])"));
  EXPECT_EQ(json["events"][0]["event"], "deadman");

  for (const std::string& name : {damaged, kDeadman, kBatteryLow}) {  // damaged, random bytes, empty
    const HttpAnswer refused = http_get("/api/records/" + name + "/messages");
    EXPECT_EQ(refused.status, 422) << name << "\n" << refused.head;
    EXPECT_EQ(header_line(refused, "Content-Type"), "application/json");
    const nlohmann::json error = nlohmann::json::parse(refused.body, nullptr, false);
    EXPECT_EQ(error["name"], name) << refused.body;
    EXPECT_NE(error.value("error", "").find("not a readable MCAP file: byte "), std::string::npos) << refused.body;
  }
  // The download's names and 404s.
  for (const std::string& target : {"/api/records/" + kPart + "/messages", "/api/records/" + kSymlink + "/messages",
                                    "/api/records/" + kDirectory + "/messages",
                                    std::string("/api/records/20261127T210000Z-deadman.mcap/messages"),
                                    std::string("/api/records/../secret.txt/messages"),
                                    "/api/records/" + good + "/messages/", "/api/records/" + good + "/other"}) {
    const HttpAnswer missing = http_get(target);
    EXPECT_EQ(missing.status, 404) << target << "\n" << missing.head;
  }
  const HttpAnswer post = http_request("POST", "/api/records/" + good + "/messages", "Content-Length: 0\r\n");
  EXPECT_EQ(post.status, 405) << post.head;
  ASSERT_TRUE(web_->running()) << web_logs();
}

}  // namespace
}  // namespace web_tests
