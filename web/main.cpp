// wheeltec-web: the live view of one robot's wheeltecd in a browser and in Foxglove (spec
// section 6, docs/web.md). Exit codes: 0 on a clean stop, 2 on bad usage or configuration,
// 1 on other failures.

#include <csignal>
#include <exception>
#include <functional>
#include <filesystem>
#include <iostream>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <spdlog/spdlog.h>

#include "options.hpp"
#include "server.hpp"
#include "static_files.hpp"
#include "tls_context.hpp"
#include "wheeltec/service/logging.hpp"

#ifndef WHEELTEC_WEB_PAGE_DIR
#define WHEELTEC_WEB_PAGE_DIR "/usr/share/wheeltec-web"
#endif

namespace {

// The page's files: the sources' when the program runs from its build directory; else the
// installed ones, PREFIX/share/wheeltec-web next to PREFIX/bin/wheeltec-web whatever the
// prefix (the .deb's /usr or cmake --install's); the configured path otherwise.
std::string default_page_dir() {
  std::error_code error;
  const auto program = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
#ifdef WHEELTEC_WEB_BUILD_DIR
    if (std::filesystem::equivalent(program.parent_path(), WHEELTEC_WEB_BUILD_DIR, error)) {
      return WHEELTEC_WEB_SOURCE_PAGE_DIR;
    }
#endif
    const auto beside = program.parent_path().parent_path() / "share" / "wheeltec-web";
    if (std::filesystem::exists(beside / "index.html", error)) return beside.string();
  }
  return WHEELTEC_WEB_PAGE_DIR;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace wheeltec::web;
  std::signal(SIGPIPE, SIG_IGN);

  auto parsed = parse_command_line(argc, argv);
  if (const int* exit_code = std::get_if<int>(&parsed)) return *exit_code;
  const Options options = std::get<Options>(std::move(parsed));

  WebConfig config;
  std::optional<std::string> token;
  std::shared_ptr<boost::asio::ssl::context> tls;
  try {
    config = load_config(options);
    if (config.token_file) token = read_token(*config.token_file);
    if (config.tls.cert && config.tls.key) tls = load_tls_context({*config.tls.cert, *config.tls.key});
  } catch (const wheeltec::ConfigError& error) {
    std::cerr << "wheeltec-web: " << error.what() << "\n";
    return 2;
  }
  if (config.page_dir.empty()) config.page_dir = default_page_dir();

  wheeltec::service::setup_logging(config.log.level, "wheeltec-web");
  try {
    StaticFiles files = StaticFiles::load(config.page_dir, config.javascript_dir);
    boost::asio::io_context io{1};
    Server server(io, std::move(config), std::move(token), std::move(files), std::move(tls));
    boost::asio::signal_set signals(io, SIGTERM, SIGINT, SIGHUP);
    std::function<void()> wait_for_signal = [&] {
      signals.async_wait([&](boost::system::error_code ec, int signal) {
        if (ec) return;
        if (signal == SIGHUP) {
          server.reload_tls();
          return wait_for_signal();
        }
        spdlog::info("signal {}: stopping", signal);
        server.stop();
        io.stop();
      });
    };
    wait_for_signal();
    server.start();
    io.run();
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "wheeltec-web: " << error.what() << "\n";
    return 1;
  }
}
