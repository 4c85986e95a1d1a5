// The harness (harness.hpp).
#include <fcntl.h>
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/timerfd.h>
#include <sys/un.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <variant>

#include <fmt/format.h>

#include "harness.hpp"
#include "wheeltec/frames/control_frame.hpp"
#include "wheeltec/frames/serial_frame.hpp"

namespace bench {

using nlohmann::json;
namespace emu = wheeltec::emulator;

namespace {

std::runtime_error system_error(const std::string& what) { return std::runtime_error(what + ": " + std::strerror(errno)); }
constexpr const char* kSubscribe = R"({"jsonrpc":"2.0","id":1,"method":"subscribe","params":{"topics":["telemetry"]}})";
double cpu_s(pid_t pid) {  // 0 when it is gone
  try {
    return sample_process(pid).cpu_s;
  } catch (const std::exception&) {
    return 0.0;
  }
}
void machine_cpu(unsigned long long& busy, unsigned long long& total) {
  std::ifstream stat("/proc/stat");
  std::string cpu;
  stat >> cpu;
  unsigned long long value = 0;
  for (int field = 0; field < 8 && stat >> value; ++field) {
    total += value;
    if (field != 3 && field != 4) busy += value;  // idle and iowait are not busy
  }
}
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

}  // namespace

// ---- clocks, /proc, command lines, child programs, counts ----
double clock_s(clockid_t clock) {
  timespec ts{};
  ::clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) / 1e9;
}
std::int64_t realtime_ns() {
  timespec ts{};
  clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}
int periodic_timer(double rate_hz, long min_interval_ns, int flags) {
  const int timer = ::timerfd_create(CLOCK_MONOTONIC, flags);
  const long interval_ns = std::max(min_interval_ns, static_cast<long>(1e9 / rate_hz));
  itimerspec spec{};
  spec.it_interval.tv_sec = interval_ns / 1'000'000'000L;
  spec.it_interval.tv_nsec = interval_ns % 1'000'000'000L;
  spec.it_value = spec.it_interval;
  ::timerfd_settime(timer, 0, &spec, nullptr);
  return timer;
}
void sleep_ms(double ms) { std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long long>(ms * 1000))); }
ProcessSample sample_process(pid_t pid) {
  const std::string dir = "/proc/" + std::to_string(pid);
  std::ifstream stat_file(dir + "/stat");
  std::string stat, field;
  if (!std::getline(stat_file, stat)) throw std::runtime_error("cannot read " + dir + "/stat");
  // The fields after the command name (which may hold spaces) start at field 3; utime is 14, stime 15.
  std::istringstream fields(stat.substr(stat.rfind(')') + 2));
  unsigned long long ticks = 0;
  for (int index = 3; index <= 15 && fields >> field; ++index) ticks += index >= 14 ? std::stoull(field) : 0;
  ProcessSample sample;
  sample.cpu_s = static_cast<double>(ticks) / static_cast<double>(sysconf(_SC_CLK_TCK));
  const std::map<std::string, std::uint64_t*> wanted = {
      {"voluntary_ctxt_switches:", &sample.voluntary_switches}, {"nonvoluntary_ctxt_switches:", &sample.involuntary_switches},
      {"VmRSS:", &sample.rss_kib}, {"VmHWM:", &sample.hwm_kib}, {"Threads:", &sample.threads}};
  std::ifstream status_file(dir + "/status");
  for (std::string line; std::getline(status_file, line);) {
    std::string key;
    std::uint64_t value = 0;
    std::istringstream(line) >> key >> value;
    if (const auto found = wanted.find(key); found != wanted.end()) *found->second = value;
  }
  return sample;
}
BenchCommandLine::BenchCommandLine(std::string name, std::string usage)
    : name_(std::move(name)), usage_(std::move(usage)), app_(name_) {
  app_.set_help_flag();
}
void BenchCommandLine::parse(int argc, char** argv) {
  if (std::any_of(argv + 1, argv + argc, [](std::string_view arg) { return arg == "-h" || arg == "--help"; })) {
    std::cout << usage_;
    std::exit(0);
  }
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    throw std::invalid_argument(error.what());
  }
}
int BenchCommandLine::run(const std::function<int()>& body) const {
  try {
    return body();
  } catch (const std::invalid_argument& error) {
    std::cerr << name_ << ": " << error.what() << "\n" << usage_;
    return 2;
  } catch (const std::exception& error) {
    std::cerr << name_ << ": " << error.what() << "\n";
    return 1;
  }
}
ChildProgram::ChildProgram(const std::string& name, const std::vector<std::string>& argv, const std::filesystem::path& log_dir)
    : name_(name), log_path_(log_dir / (name + ".log")) {
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error("fork failed");
  if (pid_ == 0) {
    const int log = ::open(log_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(::open("/dev/null", O_RDONLY), 0);
    ::dup2(log, 1);
    ::dup2(log, 2);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
}
bool ChildProgram::running() {
  if (pid_ >= 0 && ::waitpid(pid_, nullptr, WNOHANG) == pid_) pid_ = -1;
  return pid_ >= 0;
}
void ChildProgram::wait_for_socket(const std::filesystem::path& path, int timeout_s) {
  for (const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);; sleep_ms(10)) {
    if (!running()) throw std::runtime_error(name_ + " ended at start-up:\n" + log_tail());
    try {
      LineClient probe(path);
      return;
    } catch (const std::runtime_error&) {
      if (std::chrono::steady_clock::now() > deadline) throw std::runtime_error(name_ + ": socket never came up");
    }
  }
}
void ChildProgram::terminate() {
  if (!running()) return;
  ::kill(pid_, SIGTERM);
  for (int i = 0; i < 300 && running(); ++i) sleep_ms(10);
  if (!running()) return;
  ::kill(pid_, SIGKILL);
  ::waitpid(pid_, nullptr, 0);
  pid_ = -1;
}
std::string ChildProgram::log_tail() const {
  std::stringstream text;
  text << std::ifstream(log_path_).rdbuf();
  const std::string all = text.str();
  return all.size() > 2000 ? all.substr(all.size() - 2000) : all;
}
WorkDir::WorkDir(const std::string& name, const std::string& given) : path(given), keep(!given.empty()) {
  std::string pattern = (std::filesystem::temp_directory_path() / (name + ".XXXXXX")).string();
  if (keep) std::filesystem::create_directories(path);
  else if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  else path = pattern;
}
WorkDir::~WorkDir() {
  std::error_code ignored;
  if (!keep) std::filesystem::remove_all(path, ignored);
}
SyscallCount::SyscallCount(const std::string& strace, pid_t pid, const std::filesystem::path& dir, const std::string& name)
    : output_(dir / (name + ".strace")) {
  std::filesystem::remove(output_);
  strace_ = std::make_unique<ChildProgram>(
      name + "-strace", std::vector<std::string>{strace, "-c", "-f", "-o", output_.string(), "-p", std::to_string(pid)}, dir);
  // strace says "Process N attached" once it has seized the process; calls before go uncounted.
  for (int i = 0; i < 500; ++i, sleep_ms(10)) {
    std::stringstream text;
    text << std::ifstream(dir / (name + "-strace.log")).rdbuf();
    if (text.str().find("attached") != std::string::npos) return;
    if (!strace_->running()) throw std::runtime_error("strace ended: " + strace_->log_tail());
  }
  throw std::runtime_error("strace did not attach within 5 s");
}
std::map<std::string, std::uint64_t> SyscallCount::stop() {
  strace_->terminate();  // SIGTERM: strace detaches and writes its summary
  std::map<std::string, std::uint64_t> calls;
  std::ifstream in(output_);
  // Rows: "% time  seconds  usecs/call  calls  [errors]  syscall"; the last is "... total".
  for (std::string line; std::getline(in, line);) {
    std::istringstream words(line);
    std::vector<std::string> fields;
    for (std::string w; words >> w;) fields.push_back(w);
    if (fields.size() >= 5 && fields[0].find_first_not_of("0123456789.") == std::string::npos) calls[fields.back()] += std::stoull(fields[3]);
  }
  if (calls.empty()) throw std::runtime_error("strace wrote no summary to " + output_.string());
  return calls;
}

// ---- figures ----
LatencySummary summarize(std::vector<double> samples_us) {
  LatencySummary summary;
  summary.count = samples_us.size();
  if (samples_us.empty()) return summary;
  std::sort(samples_us.begin(), samples_us.end());
  const auto percentile = [&](double fraction) {
    const auto rank = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(samples_us.size())));
    return samples_us[std::clamp<std::size_t>(rank, 1, samples_us.size()) - 1];
  };
  summary.p50_us = percentile(0.50);
  summary.p99_us = percentile(0.99);
  summary.max_us = samples_us.back();
  return summary;
}
json LatencySummary::to_json() const { return {{"count", count}, {"p50_us", p50_us}, {"p99_us", p99_us}, {"max_us", max_us}}; }
json summary_with_samples(std::vector<double> samples_us) {
  json j = summarize(samples_us).to_json();
  for (auto& sample : samples_us) sample = std::round(sample);
  j["samples_us"] = samples_us;
  return j;
}
TelemetryMatch match_records(const std::vector<std::int64_t>& frames_ns, const Receipts& receipts, std::int64_t from_ns,
                             std::int64_t to_ns) {
  const std::unordered_map<std::int64_t, std::int64_t> by_time(receipts.begin(), receipts.end());
  TelemetryMatch match;
  for (const std::int64_t frame_ns : frames_ns) {
    if (frame_ns < from_ns || frame_ns >= to_ns) continue;
    ++match.on_bus;
    const std::int64_t key = frame_ns / 1000;
    auto found = by_time.find(key);
    if (found == by_time.end()) found = by_time.find(key - 1);
    if (found == by_time.end()) found = by_time.find(key + 1);
    if (found == by_time.end()) {
      match.missing_ns.push_back(frame_ns);
      continue;
    }
    ++match.delivered;
    match.latency_us.push_back(static_cast<double>(found->second - frame_ns) / 1e3);
  }
  return match;
}
json match_json(const TelemetryMatch& match, bool with_samples) {
  json j = with_samples ? summary_with_samples(match.latency_us) : summarize(match.latency_us).to_json();
  j.update({{"on_bus", match.on_bus}, {"delivered", match.delivered}, {"lost", match.lost()}});
  return j;
}
std::size_t received_between(const Receipts& receipts, std::int64_t from_ns, std::int64_t to_ns) {
  return static_cast<std::size_t>(std::count_if(receipts.begin(), receipts.end(), [&](const auto& receipt) {
    return receipt.second >= from_ns && receipt.second < to_ns;
  }));
}
json counters_delta(const json& before, const json& after) {
  json delta = json::object();
  for (const auto& [key, value] : after.items()) {
    if (value.is_number_unsigned() && before.contains(key)) delta[key] = value.get<std::uint64_t>() - before[key].get<std::uint64_t>();
    if (!value.is_object()) continue;
    delta[key] = json::object();
    const json earlier = before.value(key, json::object());
    for (const auto& [reason, count] : value.items()) {
      const auto changed = count.get<std::uint64_t>() - earlier.value(reason, std::uint64_t{0});
      if (changed > 0) delta[key][reason] = changed;
    }
  }
  return delta;
}
std::string us(double value) { return fmt::format("{:.0f}", value); }
std::string p50_p99(const json& summary) {
  if (summary.value("count", 0) == 0) return "-";
  return fmt::format("{:.0f} / {:.0f}", summary["p50_us"].get<double>(), summary["p99_us"].get<double>());
}
std::string lost_of(const TelemetryMatch& match) { return fmt::format("{} of {}", match.lost(), match.on_bus); }
void latency_row(const std::string& label, const json& summary, const std::string& lost) {
  std::cout << "| " << label << " | " << p50_p99(summary) << " | " << summary["count"].dump() << " | " << lost << " |\n";
}
std::string syscall_listing(const json& per_record) {
  std::vector<std::pair<double, std::string>> calls;
  for (const auto& [name, value] : per_record.items()) {
    if (name != "total" && value.get<double>() >= 0.05) calls.emplace_back(value.get<double>(), name);
  }
  std::sort(calls.rbegin(), calls.rend());
  std::string text;
  for (const auto& [value, name] : calls) text += fmt::format("{}{} {:.2f}", text.empty() ? "" : ", ", name, value);
  return fmt::format("{:.2f} ({})", per_record.value("total", 0.0), text);
}
int publish_table(const std::string& table, json& out, const std::string& json_path) {
  std::cout << table;
  out["table_markdown"] = table;
  if (!json_path.empty()) std::ofstream(json_path) << out.dump(2) << "\n";
  return 0;
}
void print_errors(const json& errors) {
  if (errors.empty()) return;
  std::cout << "\nErrors:\n";
  for (const auto& error : errors) std::cout << "- " << error.get<std::string>() << "\n";
}

// ---- a gateway's Unix socket ----
LineClient::LineClient(const std::filesystem::path& socket_path) {
  fd_ = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, socket_path.c_str(), sizeof(address.sun_path) - 1);
  if (fd_ < 0 || ::connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) {
    throw system_error("cannot connect to " + socket_path.string());
  }
}
void LineClient::send_line(std::string_view line) {
  const std::string out = std::string(line) + '\n';
  for (std::size_t done = 0; done < out.size();) {
    const ssize_t n = ::send(fd_, out.data() + done, out.size() - done, MSG_NOSIGNAL);
    if (n <= 0) throw system_error("send on the API socket");
    done += static_cast<std::size_t>(n);
  }
}
bool LineClient::receive(int timeout_ms) {
  pollfd ready{fd_, POLLIN, 0};
  if (timeout_ms != 0 && ::poll(&ready, 1, timeout_ms) <= 0) return false;
  char chunk[65536];
  const ssize_t n = ::recv(fd_, chunk, sizeof(chunk), MSG_DONTWAIT);
  if (n == 0) throw std::runtime_error("the gateway closed the connection");
  if (n < 0) return false;
  buffer_.append(chunk, static_cast<std::size_t>(n));
  return true;
}
std::optional<std::string> LineClient::take_line() {
  const auto end = buffer_.find('\n');
  if (end == std::string::npos) return std::nullopt;
  std::string line = buffer_.substr(0, end);
  buffer_.erase(0, end + 1);
  return line;
}
std::string LineClient::read_line(int timeout_ms) {
  for (;;) {
    if (auto line = take_line()) return *line;
    if (!receive(timeout_ms)) throw std::runtime_error("no reply from the gateway within " + std::to_string(timeout_ms) + " ms");
  }
}
std::size_t LineClient::drain_lines() {
  receive(0);  // one recv per readiness (level-triggered): to EAGAIN would cost UML a second call per wakeup
  const auto count = static_cast<std::size_t>(std::count(buffer_.begin(), buffer_.end(), '\n'));
  buffer_.erase(0, buffer_.rfind('\n') == std::string::npos ? 0 : buffer_.rfind('\n') + 1);
  return count;
}
json api_call(const std::filesystem::path& socket, const std::string& method) {
  LineClient client(socket);
  client.send_line(R"({"jsonrpc":"2.0","id":1,"method":")" + method + R"("})");
  return json::parse(client.read_line(2000)).at("result");
}
SubscriberSet::SubscriberSet(const std::filesystem::path& socket_path, std::size_t count) {
  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  for (std::size_t i = 0; i < count; ++i) {
    auto client = std::make_unique<LineClient>(socket_path);
    client->send_line(kSubscribe);
    const std::string reply = client->read_line(5000);
    if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error("subscribe failed: " + reply);
    epoll_event event{EPOLLIN, {.u64 = i}};
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, client->fd(), &event);
    clients_.push_back(std::move(client));
  }
}
std::vector<std::size_t> SubscriberSet::poll(int timeout_ms, std::vector<std::size_t>& lines, int extra_fd,
                                             bool* extra_ready) {
  if (extra_fd >= 0 && extra_fd != extra_fd_) {
    if (extra_fd_ >= 0) ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, extra_fd_, nullptr);
    epoll_event event{EPOLLIN, {.u64 = ~0ULL}};
    ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, extra_fd, &event);
    extra_fd_ = extra_fd;
  }
  if (extra_ready) *extra_ready = false;
  lines.resize(clients_.size());
  epoll_event events[128];
  std::vector<std::size_t> ready;
  const int n = ::epoll_wait(epoll_fd_, events, 128, timeout_ms);
  for (int i = 0; i < n; ++i) {
    const auto index = events[i].data.u64;
    if (index == ~0ULL && extra_ready) *extra_ready = true;
    if (index >= clients_.size()) continue;
    if (const std::size_t got = clients_[index]->drain_lines(); got > 0) {
      lines[index] += got;
      ready.push_back(index);
    }
  }
  return ready;
}
std::uint64_t SubscriberSet::read_rest(std::vector<std::size_t>& lines, std::uint64_t expected) {
  auto received = [&] { return std::accumulate(lines.begin(), lines.end(), std::uint64_t{0}); };
  for (double last_progress = now_us(); received() < expected && now_us() - last_progress < 300e3;) {
    const auto before = received();
    poll(50, lines);
    if (received() != before) last_progress = now_us();
  }
  return received();
}

// ---- CAN ----
CanEndpoint::CanEndpoint(const std::string& interface, std::vector<std::uint32_t> receive_ids) {
  fd_ = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
  if (fd_ < 0) throw system_error("socket(PF_CAN)");
  std::vector<can_filter> filters;
  for (std::uint32_t id : receive_ids) filters.push_back(can_filter{id, CAN_SFF_MASK | CAN_EFF_FLAG | CAN_RTR_FLAG});
  if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, filters.empty() ? nullptr : filters.data(),
                   static_cast<socklen_t>(filters.size() * sizeof(can_filter))) != 0) {
    throw system_error("CAN_RAW_FILTER");
  }
  sockaddr_can address{};
  address.can_family = AF_CAN;
  address.can_ifindex = static_cast<int>(::if_nametoindex(interface.c_str()));
  if (address.can_ifindex == 0) throw system_error("interface " + interface);
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0) throw system_error("bind " + interface);
  const int on = 1;
  if (::setsockopt(fd_, SOL_SOCKET, SO_TIMESTAMPNS, &on, sizeof(on)) != 0) throw system_error("SO_TIMESTAMPNS");
}
void CanEndpoint::send(const wheeltec::CanFrame& frame) {
  const can_frame raw = wheeltec::asio_can::to_socketcan(frame);
  // A full transmit queue (ENOBUFS) under a flood: wait for room rather than lose the frame.
  for (int attempt = 0; attempt < 1000; ++attempt) {
    if (::write(fd_, &raw, sizeof(raw)) == static_cast<ssize_t>(sizeof(raw))) return;
    if (errno != ENOBUFS && errno != EAGAIN && errno != EINTR) throw system_error("CAN write");
    pollfd ready{fd_, POLLOUT, 0};
    ::poll(&ready, 1, 1);
  }
  throw std::runtime_error("CAN write: the transmit queue stayed full for 1 s");
}
std::optional<wheeltec::asio_can::ReceivedFrame> CanEndpoint::receive(int timeout_ms) {
  pollfd ready{fd_, POLLIN, 0};
  if (::poll(&ready, 1, timeout_ms) <= 0) return std::nullopt;
  boost::system::error_code error;
  return wheeltec::asio_can::receive_frame(fd_, error);
}
void CanEndpoint::drain() {
  boost::system::error_code ec;
  while (wheeltec::asio_can::receive_frame(fd_, ec)) {}
}
std::optional<std::int64_t> record_time_us(const std::string& json_text) {
  const auto at = json_text.find("\"time\":");
  if (at == std::string::npos || json_text.find_first_of(",}", at) == std::string::npos) return std::nullopt;
  // Seconds with up to 6 decimals: a double holds 1.8e15 us to 0.25 us, so rounding gives the daemon's.
  const char* start = json_text.c_str() + at + 7;
  char* end = nullptr;
  const double seconds = std::strtod(start, &end);
  if (end == start) return std::nullopt;
  return std::llround(seconds * 1e6);
}
std::optional<std::int64_t> record_seq(const std::string& json_text) {
  const auto at = json_text.find("\"seq\":");
  if (at == std::string::npos || json_text.find_first_of(",}", at) == std::string::npos) return std::nullopt;
  return std::strtoll(json_text.c_str() + at + 6, nullptr, 10);
}
BusObserver::BusObserver(const std::vector<std::string>& interfaces,
                         const std::optional<std::filesystem::path>& daemon_socket) {
  for (const auto& interface : interfaces) sockets_.push_back(std::make_unique<CanEndpoint>(interface, std::vector<std::uint32_t>{0x103}));
  frames_.resize(sockets_.size());
  if (daemon_socket) {
    direct_ = std::make_unique<LineClient>(*daemon_socket);
    direct_->send_line(kSubscribe);
    // The reply comes first; the thread reads the telemetry after it.
    const std::string reply = direct_->read_line(5000);
    if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error("direct subscription refused: " + reply);
  }
  thread_ = std::thread([this] { run(); });
}
BusObserver::~BusObserver() {
  stop_.raise();
  thread_.join();
}
void BusObserver::run() {
  std::vector<pollfd> fds;
  for (const auto& socket : sockets_) fds.push_back(pollfd{socket->fd(), POLLIN, 0});
  if (direct_) fds.push_back(pollfd{direct_->fd(), POLLIN, 0});
  fds.push_back(pollfd{stop_.fd, POLLIN, 0});
  for (;;) {
    if (::poll(fds.data(), fds.size(), -1) < 0 && errno != EINTR) return;
    if (fds.back().revents != 0) return;
    for (std::size_t i = 0; i < sockets_.size(); ++i) {
      boost::system::error_code ec;
      if (fds[i].revents == 0) continue;
      while (auto received = wheeltec::asio_can::receive_frame(sockets_[i]->fd(), ec)) {
        std::lock_guard lock(mutex_);
        frames_[i].push_back(received->time.time_since_epoch().count());
      }
    }
    if (!direct_ || fds[sockets_.size()].revents == 0) continue;
    try {
      direct_->receive(0);
    } catch (const std::runtime_error&) {  // the daemon went away: poll() skips it from now on
      direct_.reset();
      fds[sockets_.size()].fd = -1;
      continue;
    }
    const std::int64_t now = realtime_ns();
    while (const auto line = direct_->take_line()) {
      if (line->find("\"method\":\"telemetry\"") == std::string::npos) continue;
      if (const auto time = record_time_us(*line)) {
        std::lock_guard lock(mutex_);
        direct_notifications_.emplace_back(*time, now);
      }
    }
  }
}
std::vector<std::int64_t> BusObserver::record_frames(std::size_t index) const {
  std::lock_guard lock(mutex_);
  return index < frames_.size() ? frames_[index] : std::vector<std::int64_t>{};
}
Receipts BusObserver::direct_notifications() const {
  std::lock_guard lock(mutex_);
  return direct_notifications_;
}

// ---- the chassis on a serial line ----
emu::PseudoTerminal open_pty() {
  auto opened = emu::open_raw_pseudo_terminal();
  if (auto* error = std::get_if<std::string>(&opened)) throw std::runtime_error(*error);
  return std::get<emu::PseudoTerminal>(opened);
}
void write_all(int fd, std::span<const std::uint8_t> bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EINTR) throw system_error("pty write");
    pollfd room{fd, POLLOUT, 0};
    ::poll(&room, 1, 10);
  }
}
PtyEndpoint::PtyEndpoint(const std::filesystem::path& link) : link_(link) {
  const emu::PseudoTerminal pty = open_pty();
  master_ = pty.master_fd;
  slave_path_ = pty.slave_path;
  slave_keeper_ = ::open(slave_path_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_keeper_ < 0) throw system_error("cannot open " + slave_path_);
  if (auto error = emu::publish_symlink(link_, slave_path_)) throw std::runtime_error(*error);
}
PtyEndpoint::~PtyEndpoint() {
  emu::remove_symlink_to(link_, slave_path_);
  ::close(slave_keeper_);
  ::close(master_);
}
bool PtyEndpoint::fill(int timeout_ms) {
  pollfd ready{master_, POLLIN, 0};
  if (::poll(&ready, 1, timeout_ms) <= 0) return false;
  std::uint8_t chunk[4096];
  const ssize_t n = ::read(master_, chunk, sizeof(chunk));
  if (n <= 0) return false;
  pending_.insert(pending_.end(), chunk, chunk + n);
  return true;
}
std::optional<double> PtyEndpoint::await_command(int x_mm_s, int timeout_ms) {
  using wheeltec::serial::kCommandFrameSize;
  const double deadline = now_us() + timeout_ms * 1e3;
  for (std::size_t at = 0;; at = 0) {
    // Sliding: a window that is not a frame costs one byte, not eleven.
    for (; at + kCommandFrameSize <= pending_.size(); ++at) {
      const auto frame = wheeltec::serial::decode_command_frame(
          std::span<const std::uint8_t, kCommandFrameSize>(pending_.data() + at, kCommandFrameSize));
      if (!frame) continue;
      at += kCommandFrameSize - 1;
      if (frame->command.x != x_mm_s) continue;
      const double read_at = now_us();
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at + 1));
      return read_at;
    }
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(at));
    const double left_ms = (deadline - now_us()) / 1e3;
    if (left_ms <= 0) return std::nullopt;
    fill(static_cast<int>(left_ms) + 1);
  }
}
void PtyEndpoint::drain() {
  while (fill(0)) {}
  pending_.clear();
}
RecordStream::RecordStream(PtyEndpoint& line, double hz)
    : thread_([this, &line, hz](std::stop_token stop) {
        const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / hz));
        std::mutex sleeping;
        std::condition_variable_any woken;
        for (auto [n, next] = std::pair{0, std::chrono::steady_clock::now()}; !stop.stop_requested(); ++n, next += period) {
          try {
            line.write(wheeltec::encode_record(bench_record(n)));
          } catch (const std::exception& error) {
            std::lock_guard lock(mutex_);
            failure_ = error.what();
            return;
          }
          std::unique_lock lock(sleeping);
          woken.wait_until(lock, stop, next + period, [] { return false; });
        }
      }) {}
std::optional<std::string> RecordStream::failure() const {
  std::lock_guard lock(mutex_);
  return failure_;
}
void wait_until_ready(const std::filesystem::path& socket, ChildProgram& daemon, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  json status;
  do {
    status = api_call(socket, "status");
    if (status["bus"]["state"] == "up" && status["chassis"]["online"] == true && status["chassis"]["phase"] == "ready") return;
    sleep_ms(50);
  } while (std::chrono::steady_clock::now() < deadline);
  throw std::runtime_error(fmt::format("the chassis did not become ready within {} s; last status {}\n{}",
                                       timeout_ms / 1000.0, status.dump(), daemon.log_tail()));
}

// ---- where the commands are seen, and a gateway's two latencies ----
CommandFrames can_command_frames(const std::string& interface) {
  auto control = std::make_shared<CanEndpoint>(interface, std::vector<std::uint32_t>{0x121});
  // The kernel time of the first 0x121 velocity frame with vx = mm_per_s (the enable handshake's frames aside).
  return {[control] { control->drain(); }, [control](int mm_per_s, int timeout_ms) -> std::optional<std::int64_t> {
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
            while (std::chrono::steady_clock::now() < deadline) {
              const auto received = control->receive(std::min(50, timeout_ms));
              if (!received) continue;
              const auto command = wheeltec::decode_control_frame(wheeltec::Dialect::manual, received->frame);
              if (command && command->x == mm_per_s) return received->time.time_since_epoch().count();
            }
            return std::nullopt;
          }};
}
CommandFrames pty_command_frames(PtyEndpoint& line) {
  return {[&line] { line.drain(); }, [&line](int mm_per_s, int timeout_ms) -> std::optional<std::int64_t> {
            const std::optional<double> read_us = line.await_command(mm_per_s, timeout_ms);
            if (!read_us) return std::nullopt;
            return realtime_ns() - std::llround((now_us() - *read_us) * 1e3);  // read on CLOCK_MONOTONIC
          }};
}
wheeltec::RawTelemetry bench_record(int n) {
  return {.vx = static_cast<std::int16_t>(n % 500), .accel_z = 16400, .battery_mv = 22500};
}
wheeltec::TelemetryGroup bench_group(int n) { return wheeltec::make_telemetry_group(wheeltec::encode_record(bench_record(n))); }
void CommandLatency::append(const CommandLatency& other) {
  total.insert(total.end(), other.total.begin(), other.total.end());
  to_frame.insert(to_frame.end(), other.to_frame.begin(), other.to_frame.end());
}
json CommandLatency::to_json() const {
  json j = summarize(total).to_json();
  j["to_frame"] = summarize(to_frame).to_json();
  return j;
}
CommandLatency command_latency(const std::filesystem::path& socket, int commands, int base_mm_per_s,
                               const std::function<std::optional<double>(int mm_per_s)>& await_frame) {
  LineClient client(socket);
  CommandLatency result;
  for (int i = 0; i < commands; ++i) {
    const int mm_per_s = base_mm_per_s + (i % 2) * 100;  // a changed target each time: one frame at once
    const std::string line = fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"drive","params":{{"vx":{}}}}})",
                                         i + 1, mm_per_s / 1000.0);
    const double start = now_us();
    client.send_line(line);
    const std::optional<double> frame_us = await_frame(mm_per_s);
    if (!frame_us) throw std::runtime_error("no command frame within 1 s after drive #" + std::to_string(i + 1));
    result.total.push_back(now_us() - start);
    result.to_frame.push_back(*frame_us - start);
    const std::string reply = client.read_line(1000);
    if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error("drive failed: " + reply);
  }
  client.send_line(R"({"jsonrpc":"2.0","id":0,"method":"stop"})");
  client.read_line(1000);
  return result;
}
namespace {
void expect_result(const std::string& reply, const char* what) {
  if (reply.find("\"result\"") == std::string::npos) throw std::runtime_error(std::string(what) + " failed: " + reply);
}
// Round `round` of a latch measurement: a drive at mm_per_s, its frame awaited and its answer read.
void drive_for_round(LineClient& driver, int round, int mm_per_s, const char* measurement,
                     const std::function<std::optional<double>(int mm_per_s)>& await_frame) {
  driver.send_line(fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"drive","params":{{"vx":{}}}}})", round,
                               mm_per_s / 1000.0));
  if (!await_frame(mm_per_s)) throw std::runtime_error(fmt::format("{} round {}: no drive frame", measurement, round));
  expect_result(driver.read_line(1000), "drive");
}
void release(LineClient& operator_) {
  operator_.send_line(R"({"jsonrpc":"2.0","id":2,"method":"release"})");
  expect_result(operator_.read_line(1000), "release");
}
}  // namespace
std::vector<double> estop_latency(const std::filesystem::path& socket, int rounds,
                                  const std::function<std::optional<double>(int mm_per_s)>& await_frame) {
  LineClient driver(socket);
  LineClient operator_(socket);
  std::vector<double> samples;
  for (int i = 0; i < rounds; ++i) {
    drive_for_round(driver, i + 1, 150 + i % 50, "estop", await_frame);
    const double start = now_us();
    operator_.send_line(R"({"jsonrpc":"2.0","id":1,"method":"estop","params":{"reason":"bench"}})");
    const std::optional<double> zero_us = await_frame(0);
    if (!zero_us) throw std::runtime_error("estop round " + std::to_string(i + 1) + ": no zero frame within 1 s");
    samples.push_back(*zero_us - start);
    expect_result(operator_.read_line(1000), "estop");
    release(operator_);
  }
  return samples;
}
std::vector<double> collision_latency(const std::filesystem::path& socket, int rounds,
                                      const std::function<double(std::int16_t vx_mm_s)>& write_record,
                                      const std::function<std::optional<double>(int mm_per_s)>& await_frame) {
  LineClient driver(socket);
  LineClient operator_(socket);
  std::vector<double> samples;
  for (int i = 0; i < rounds; ++i) {
    const int mm_per_s = 500 + i % 50;  // a fall to 0 is beyond the default drop (0.25 m/s)
    drive_for_round(driver, i + 1, mm_per_s, "collision", await_frame);
    for (int moving = 0; moving < 2; ++moving) {
      write_record(static_cast<std::int16_t>(mm_per_s));
      sleep_ms(50);
    }
    const double start = write_record(0);
    const std::optional<double> zero_us = await_frame(0);
    if (!zero_us) throw std::runtime_error("collision round " + std::to_string(i + 1) + ": no zero frame within 1 s");
    samples.push_back(*zero_us - start);
    const json safety = api_call(socket, "status")["safety"];
    if (safety.value("source", "") != "collision") {
      throw std::runtime_error("collision round " + std::to_string(i + 1) + ": latched by " + safety.dump());
    }
    release(operator_);
  }
  return samples;
}
json TelemetryLatency::to_json() const {
  json j = all.to_json();
  j["lost"] = lost;
  return j;
}
TelemetryLatency telemetry_latency(const std::filesystem::path& socket, std::size_t subscribers, int records,
                                   const std::function<double(int n)>& send_record) {
  SubscriberSet set(socket, subscribers);
  std::vector<std::size_t> lines(subscribers, 0);
  std::vector<double> samples;
  samples.reserve(subscribers * records);
  TelemetryLatency result;
  for (int r = 0; r < records; ++r) {
    const double start = send_record(r);
    std::size_t waiting = subscribers;
    std::vector<bool> got(subscribers, false);
    while (waiting > 0 && now_us() < start + 1e6) {
      for (std::size_t index : set.poll(100, lines)) {
        if (got[index]) continue;
        got[index] = true;
        --waiting;
        samples.push_back(now_us() - start);
      }
    }
    result.lost += waiting;
  }
  result.all = summarize(std::move(samples));
  return result;
}

// ---- the bridge benchmarks ----
Robot::Robot(const FleetPrograms& programs, std::filesystem::path directory, std::string name, std::string interface,
             const std::filesystem::path& serial_device)
    : programs(programs), directory(std::move(directory)), name(std::move(name)), interface(std::move(interface)),
      socket(this->directory / "wheeltecd.sock") {
  std::filesystem::create_directories(this->directory);
  // As the integration tests' Gateway configures the daemon.
  json daemon_config = {{"chassis", {{"type", "mecanum"}}}, {"telemetry", {{"timeout_s", 0.5}}}, {"log", {{"level", "warn"}}},
                        {"control", {{"rate_hz", 20}, {"command_timeout_s", 0.5}, {"enable_refresh_s", 1.0}}},
                        {"api", {{"socket", socket.string()}}}};
  if (serial_device.empty()) daemon_config["can"] = {{"interface", this->interface}, {"dialect", "manual"}};
  else daemon_config.update({{"transport", "serial"}, {"serial", {{"device", serial_device.string()}}}});
  std::ofstream(this->directory / "wheeltecd.json") << daemon_config.dump(2) << "\n";
  // stats every second, so that its counters are fresh at the end of each window.
  const json bridge_config = {{"stats", {{"period_s", 1}}}, {"broker", {{"reconnect_min_s", 0.2}, {"reconnect_max_s", 1}}}};
  std::ofstream(this->directory / "wheeltec-mqtt.json") << bridge_config.dump(2) << "\n";
  ::chmod((this->directory / "wheeltec-mqtt.json").c_str(), 0600);  // the bridge refuses a file others may read
}
void Robot::start_emulator() {
  emulator = std::make_unique<ChildProgram>("wheeltec-emu", std::vector<std::string>{programs.emulator, "--interface", interface,
      "--chassis", "mecanum", "--boot-delay", "0", "--battery", "22.5", "--no-self-test"}, directory);
}
void Robot::start_daemon() {
  daemon = std::make_unique<ChildProgram>("wheeltecd", std::vector<std::string>{programs.wheeltecd, "--config",
      (directory / "wheeltecd.json").string()}, directory);
  daemon->wait_for_socket(socket, 30);
}
std::unique_ptr<ChildProgram> Robot::launch_bridge(const std::string& program, int broker_port, const std::string& robot) const {
  return std::make_unique<ChildProgram>(program, std::vector<std::string>{programs.bridge, "--config",
      (directory / "wheeltec-mqtt.json").string(), "--socket", socket.string(), "--broker", "127.0.0.1:" + std::to_string(broker_port),
      "--robot", robot, "--log-level", "info"}, directory);
}
std::unique_ptr<ChildProgram> Robot::launch_paho_bridge(const std::string& program, int broker_port, const std::string& robot) const {
  return std::make_unique<ChildProgram>(program, std::vector<std::string>{"/usr/bin/python3", programs.paho_bridge,
      "--socket", socket.string(), "--broker", "127.0.0.1:" + std::to_string(broker_port), "--robot", robot}, directory);
}
void Robot::start_bridge(int broker_port) { bridge = launch_bridge("wheeltec-mqtt", broker_port, name); }
void Robot::start_paho_bridge(int broker_port, const std::string& robot) {
  paho_bridge = launch_paho_bridge("paho-bridge", broker_port, robot);
}
constexpr std::pair<std::unique_ptr<ChildProgram> Robot::*, const char*> kRobotPrograms[] = {
    {&Robot::emulator, "wheeltec-emu"}, {&Robot::daemon, "wheeltecd"}, {&Robot::bridge, "wheeltec-mqtt"}, {&Robot::paho_bridge, "paho bridge"}};
std::vector<std::string> Robot::ended() {
  std::vector<std::string> names;
  for (const auto& [program, what] : kRobotPrograms) {
    if (this->*program && !(this->*program)->running()) names.push_back(name + "'s " + what);
  }
  return names;
}
std::string Robot::logs() const {
  std::string text;
  for (const auto& [program, what] : kRobotPrograms) {
    if (this->*program) text += "--- " + name + " " + what + ":\n" + (this->*program)->log_tail();
  }
  return text;
}
void DriveSeries::add(int mm_per_s, std::int64_t sent_ns, std::optional<std::int64_t> frame_ns) {
  if (!frame_ns) {
    ++missed;
    return;
  }
  latency_us.push_back(static_cast<double>(*frame_ns - sent_ns) / 1e3);
  timed.push_back({mm_per_s, sent_ns, *frame_ns});
}
json DriveSeries::to_json() const {
  json j = summary_with_samples(latency_us);
  j["missed"] = missed;
  return j;
}
int next_target(int& mm_per_s, int base) { return mm_per_s = base + (mm_per_s - base + 1) % 100; }
void drive_in_alternating_blocks(std::vector<DrivePath>& paths, const DriveSchedule& schedule) {
  const auto run_block = [&](DrivePath& path, int count, bool counted) {
    path.open();
    const double cpu0 = path.cpu_of >= 0 ? cpu_s(path.cpu_of) : 0.0;
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < count; ++i) {
      std::this_thread::sleep_until(start + std::chrono::microseconds(static_cast<long long>(i * schedule.interval_ms * 1000)));
      path.drive(counted);
    }
    if (counted && path.cpu_of >= 0) path.cpu_s += cpu_s(path.cpu_of) - cpu0;
    path.stop();
  };
  for (auto& path : paths) {
    if (path.warm_up) run_block(path, 3, false);
  }
  for (int done = 0; done < schedule.drives; done += schedule.block) {
    for (auto& path : paths) run_block(path, std::min(schedule.block, schedule.drives - done), true);
  }
}
void stop_on(LineClient& client, std::vector<std::string>& first_errors) {
  client.send_line(R"({"jsonrpc":"2.0","id":0,"method":"stop"})");
  const std::string reply = client.read_line(2000);
  if (reply.find("\"result\"") == std::string::npos && first_errors.size() < 5) first_errors.push_back("stop: " + reply);
}
DrivePath socket_drives(const std::filesystem::path& socket, const CommandFrames& frames, DriveSeries& series,
                        std::vector<std::string>& first_errors) {
  auto client = std::make_shared<std::unique_ptr<LineClient>>();
  auto mm_per_s = std::make_shared<int>(100);
  DrivePath path;
  path.open = [=] { *client = std::make_unique<LineClient>(socket); };
  path.drive = [=, &frames, &series, &first_errors](bool counted) {
    const int mm = next_target(*mm_per_s, 100);
    frames.drain();
    const std::string line = fmt::format(R"({{"jsonrpc":"2.0","id":{},"method":"drive","params":{{"vx":{:.3f}}}}})", mm, mm / 1000.0);
    const std::int64_t sent = realtime_ns();
    (*client)->send_line(line);
    const auto frame = frames.first_with(mm, 1000);
    if (const std::string reply = (*client)->read_line(2000); reply.find("\"result\"") == std::string::npos && first_errors.size() < 5) {
      first_errors.push_back("direct drive: " + reply);
    }
    if (counted) series.add(mm, sent, frame);
  };
  path.stop = [=, &first_errors] {
    stop_on(**client, first_errors);
    client->reset();
  };
  return path;
}
void parse_bridge_options(BenchCommandLine& command_line, BridgeSettings& s, const QuickRun& quick, int argc, char** argv,
                          const std::function<void()>& own) {
  for (const auto& [flag, into] : {std::pair{"--wheeltecd", &s.programs.wheeltecd}, {"--emulator", &s.programs.emulator},
                                   {"--bridge", &s.programs.bridge}, {"--json", &s.json_path}, {"--work-dir", &s.work_dir},
                                   {"--strace", &s.strace}}) {
    command_line.value(flag, *into);
  }
  command_line.value("--telemetry-seconds", s.telemetry_s);
  command_line.value("--drives", s.drives.drives);
  command_line.value("--drive-interval-ms", s.drives.interval_ms);
  command_line.flag("--quick", s.quick);
  own();
  command_line.parse(argc, argv);
  if (s.quick) {
    if (!command_line.given("--telemetry-seconds")) s.telemetry_s = quick.telemetry_s;
    if (!command_line.given("--drives")) s.drives.drives = quick.drives;
    s.drives.block = quick.drive_block;
  }
  if (s.drives.drives < 2 || s.telemetry_s <= 0 || s.drives.interval_ms <= 0) throw std::invalid_argument("nothing to measure");
}
CpuWindow::CpuWindow(std::vector<pid_t> pids) : pids_(std::move(pids)) {
  from_ns = realtime_ns();
  for (const pid_t pid : pids_) before_.push_back(bench::cpu_s(pid));
  machine_cpu(busy_[0], total_[0]);
}
void CpuWindow::close() {
  to_ns = realtime_ns();
  for (const pid_t pid : pids_) after_.push_back(bench::cpu_s(pid));
  machine_cpu(busy_[1], total_[1]);
}
double CpuWindow::busy_pct() const {
  return total_[1] > total_[0] ? 100.0 * static_cast<double>(busy_[1] - busy_[0]) / static_cast<double>(total_[1] - total_[0]) : 0.0;
}
json syscalls_per_record(const std::string& strace, const std::filesystem::path& work, double seconds,
                         const std::vector<std::tuple<std::string, std::string, pid_t>>& programs, const std::function<void(double ms)>& wait,
                         const std::function<std::size_t(std::int64_t, std::int64_t)>& records_between) {
  std::vector<std::unique_ptr<SyscallCount>> counts;
  for (const auto& [name, key, pid] : programs) counts.push_back(std::make_unique<SyscallCount>(strace, pid, work, name));
  const std::int64_t from_ns = realtime_ns();
  wait(seconds * 1000);
  const std::int64_t to_ns = realtime_ns();
  std::vector<std::map<std::string, std::uint64_t>> calls;
  for (auto& count : counts) calls.push_back(count->stop());
  wait(500);  // records of the window still on their way
  const std::size_t records = records_between(from_ns, to_ns);
  json figures = {{"seconds", static_cast<double>(to_ns - from_ns) / 1e9}, {"records", records}};
  for (std::size_t i = 0; i < programs.size(); ++i) {
    json& per_record = figures[std::get<1>(programs[i])] = json::object();
    for (const auto& [name, n] : calls[i]) per_record[name] = records == 0 ? 0.0 : static_cast<double>(n) / static_cast<double>(records);
  }
  return figures;
}
json start_figures(const BridgeSettings& settings, const json& own) {
  json out = {{"machine", {{"cpus", std::thread::hardware_concurrency()}, {"load_average_at_start", load_average()},
                           {"user_mode_linux", std::getenv("VCAN_RUN_IN_UML") != nullptr}}},
              {"settings", {{"quick", settings.quick}, {"telemetry_seconds", settings.telemetry_s}, {"drives", settings.drives.drives},
                            {"drive_block", settings.drives.block}, {"drive_interval_ms", settings.drives.interval_ms}}}};
  out["settings"].update(own);
  return out;
}
int finish_figures(const BridgeSettings& settings, json& out, const json& errors, std::chrono::steady_clock::time_point started) {
  out["errors"] = errors;
  out["load_average_at_end"] = load_average();
  out["elapsed_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::cout.flush();
  if (!settings.json_path.empty()) std::ofstream(settings.json_path) << out.dump(2) << "\n";
  return errors.empty() ? 0 : 1;
}

}  // namespace bench
