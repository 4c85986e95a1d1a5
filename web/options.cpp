#include "options.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"
#include "wheeltec/config/config_checks.hpp"
#include "wheeltec/service/config_file.hpp"
#include "wheeltec/service/layered_config.hpp"

namespace wheeltec::web {

std::variant<Options, int> parse_command_line(int argc, char** argv) {
  Options options;
  CLI::App app{"wheeltec-web: live view of a WHEELTEC robot in a browser and in Foxglove", "wheeltec-web"};
  command_line::add_bridge_flags(app, options, kDefaultConfigFile);
  app.add_option("--listen", options.listen, "Address and port to serve on, default 127.0.0.1:8080")
      ->type_name("ADDR:PORT");
  app.add_option("--token-file", options.token_file,
                 "File holding the token that driving needs (not readable by others); without it nobody drives")
      ->type_name("FILE");
  app.add_option("--allow-origin", options.allow_origins,
                 "Another web origin whose pages may connect, e.g. https://app.foxglove.dev (repeatable)")
      ->type_name("ORIGIN");
  app.add_option("--page-dir", options.page_dir, "Directory of the page's files, default the installed ones")
      ->type_name("DIR");
  app.add_option("--record-dir", options.record_dir,
                 "Directory of wheeltec-record's files to list and serve, default /var/lib/wheeltec-record")
      ->type_name("DIR");
  app.add_option("--tls-cert", options.tls_cert,
                 "Certificate (PEM, with its intermediates) to serve https:// and wss:// only; needs --tls-key")
      ->type_name("FILE");
  app.add_option("--tls-key", options.tls_key, "The certificate's private key (PEM, not readable by others)")
      ->type_name("FILE");
  return command_line::parse_bridge_command_line(app, options, argc, argv);
}

WebConfig load_config(const Options& options) {
  WebConfig defaults;
  defaults.socket = client::socket_path_from_environment();
  const service::ConfigLayers<WebConfig> layers{kDefaultConfigFile, service::ConfigSecrecy::open, apply_web_config,
                                                validate_web_config};
  return service::load_layered_config(std::move(defaults), options, layers, [&](WebConfig& config) {
    if (options.listen) {
      config.listen = config_checks::parse_host_port(*options.listen, "--listen", config_checks::PortUse::listen);
    }
    if (options.token_file) config.token_file = *options.token_file;
    for (const auto& origin : options.allow_origins) config.allow_origins.push_back(origin);
    if (options.page_dir) config.page_dir = *options.page_dir;
    if (options.record_dir) config.record_dir = *options.record_dir;
    if (options.tls_cert) config.tls.cert = *options.tls_cert;
    if (options.tls_key) config.tls.key = *options.tls_key;
  });
}

std::string read_token(const std::string& path) {
  const std::string token = token_from_file_content(service::read_config_file(path, service::ConfigSecrecy::private_));
  if (token.empty()) throw ConfigError(fmt::format("token file {} is empty", path));
  return token;
}

}  // namespace wheeltec::web
