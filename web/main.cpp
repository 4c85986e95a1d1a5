// wheeltec-web: the live view of one robot's wheeltecd in a browser and in Foxglove (spec
// section 6, docs/web.md). Exit codes: 0 on a clean stop, 2 on bad usage or configuration,
// 1 on other failures.

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include <boost/asio/io_context.hpp>

#include "options.hpp"
#include "server.hpp"
#include "static_files.hpp"
#include "tls_context.hpp"
#include "wheeltec/service/logging.hpp"
#include "wheeltec/service/program.hpp"

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

// What the server needs before it starts: a token and a TLS context that do not load are
// configuration errors (exit 2).
struct Setup {
  wheeltec::web::WebConfig config;
  std::optional<std::string> token;
  std::shared_ptr<boost::asio::ssl::context> tls;
};

Setup load_setup(const wheeltec::web::Options& options) {
  using namespace wheeltec::web;
  Setup setup{load_config(options), std::nullopt, nullptr};
  if (setup.config.token_file) setup.token = read_token(*setup.config.token_file);
  if (setup.config.tls.cert && setup.config.tls.key) {
    setup.tls = load_tls_context({*setup.config.tls.cert, *setup.config.tls.key});
  }
  if (setup.config.page_dir.empty()) setup.config.page_dir = default_page_dir();
  return setup;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace wheeltec::web;
  return wheeltec::service::run_program(
      "wheeltec-web", argc, argv, parse_command_line, load_setup, [](const Options& /*options*/, Setup& setup) {
        wheeltec::service::setup_logging(setup.config.log.level, "wheeltec-web");
        StaticFiles files = StaticFiles::load(setup.config.page_dir, setup.config.javascript_dir);
        boost::asio::io_context io{1};
        Server server(io, std::move(setup.config), std::move(setup.token), std::move(files), std::move(setup.tls));
        wheeltec::service::serve_until_stopped(io, server, [&] { server.reload_tls(); });
        return 0;
      });
}
