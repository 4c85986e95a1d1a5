#include <iostream>
#include <string>

#include "cli_error.hpp"
#include "commands.hpp"
#include "daemon_session.hpp"
#include "human_format.hpp"

namespace wheeltecctl {
namespace {

// A topic's notifications printed one line each, until `count` lines were printed (0: until
// SIGINT, SIGTERM or SIGHUP, exit 0).
class TopicStream {
 public:
  TopicStream(const GlobalOptions& options, std::uint64_t count) : daemon_(options.socket_path), count_(count) {
    daemon_.catch_interrupts();
  }

  wheeltec::client::Connection& connection() { return daemon_.connection(); }

  void print(const std::string& line) {
    if (done()) return;
    std::cout << line << std::endl;
    ++printed_;
  }

  int run(const char* topic) {
    daemon_.call("subscribe", Json{{"topics", Json::array({topic})}});
    daemon_.wait(std::nullopt, [&] { return done(); });
    return kExitOk;
  }

 private:
  bool done() const { return count_ != 0 && printed_ >= count_; }

  DaemonSession daemon_;
  std::uint64_t count_;
  std::uint64_t printed_ = 0;
};

}  // namespace

int run_watch(const GlobalOptions& options, std::uint64_t count) {
  TopicStream stream(options, count);
  stream.connection().on_telemetry([&](const wheeltec::client::Telemetry& record) {
    stream.print(options.json ? record.json.dump() : format_telemetry_line(record.json));
  });
  return stream.run("telemetry");
}

int run_events(const GlobalOptions& options, std::uint64_t count) {
  TopicStream stream(options, count);
  stream.connection().on_event([&](const Json& event) {
    stream.print(options.json ? event.dump(-1, ' ', false, Json::error_handler_t::replace) : format_event_line(event));
  });
  return stream.run("events");
}

}  // namespace wheeltecctl
