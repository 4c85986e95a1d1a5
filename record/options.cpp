#include "options.hpp"

#include <chrono>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "wheeltec/client/connection.hpp"
#include "wheeltec/command_line.hpp"
#include "wheeltec/service/layered_config.hpp"
#include "wheeltec/version.hpp"

#include "directory_store.hpp"

namespace wheeltec::record {
namespace {

std::chrono::nanoseconds nanoseconds(double seconds) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(seconds));
}

// The program's own flags over the config file.
void apply_flags(const Options& options, RecorderConfig& c) {
  if (options.dir) c.dir = *options.dir;
  if (options.before_s) c.before_s = *options.before_s;
  if (options.after_s) c.after_s = *options.after_s;
  if (options.max_bytes) c.max_bytes = *options.max_bytes;
  if (options.continuous) c.continuous = true;
  if (options.split_s) c.split_s = *options.split_s;
  c.triggers = apply_trigger_options(c.triggers, options.triggers, options.no_triggers);
}

}  // namespace

std::variant<Options, int> parse_command_line(int argc, char** argv) {
  Options options;
  CLI::App app{"wheeltec-record: the black box of a WHEELTEC robot; writes the time around each incident to an "
               "MCAP file",
               "wheeltec-record"};
  command_line::add_bridge_flags(app, options, kDefaultConfigFile);
  app.add_option("--dir", options.dir, "Directory of the files, overrides dir; default /var/lib/wheeltec-record")
      ->type_name("DIR");
  app.add_option("--before", options.before_s, "Seconds kept before a trigger, overrides before_s; default 60")
      ->type_name("S")
      ->check(command_line::finite_in(0.0, kMaxBeforeS, command_line::LowBound::exclusive));
  app.add_option("--after", options.after_s, "Seconds recorded after a trigger, overrides after_s; default 10")
      ->type_name("S")
      ->check(command_line::finite_in(0.0, kMaxAfterS));
  app.add_option("--max-bytes", options.max_bytes, "The files' total size at most, oldest deleted first; default 1 GiB")
      ->type_name("N")
      ->check(CLI::PositiveNumber);
  app.add_flag("--continuous", options.continuous, "Also record everything, into files of --split seconds");
  app.add_option("--split", options.split_s, "Seconds of a continuous file, overrides split_s; default 600")
      ->type_name("S")
      ->check(command_line::finite_in(1.0, 86400.0));
  app.add_option("--trigger", options.triggers, "Turn a trigger on (repeatable)")->type_name("NAME");
  app.add_option("--no-trigger", options.no_triggers, "Turn a trigger off (repeatable)")->type_name("NAME");
  return command_line::parse_bridge_command_line(app, options, argc, argv);
}

RecorderConfig load_config(const Options& options) {
  RecorderConfig defaults;
  defaults.socket = client::socket_path_from_environment();  // as wheeltecctl finds it
  const service::ConfigLayers<RecorderConfig> layers{kDefaultConfigFile, service::ConfigSecrecy::open,
                                                     apply_recorder_config, validate_recorder_config};
  RecorderConfig config = service::load_layered_config(std::move(defaults), options, layers,
                                                       [&](RecorderConfig& c) { apply_flags(options, c); });
  prepare_directory(config.dir);
  return config;
}

BlackBoxSettings black_box_settings(const RecorderConfig& config) {
  BlackBoxSettings settings;
  settings.before = nanoseconds(config.before_s);
  settings.after = nanoseconds(config.after_s);
  settings.triggers = config.triggers;
  settings.max_bytes = config.max_bytes;
  if (config.continuous) settings.continuous_split = nanoseconds(config.split_s);
  settings.library = std::string("wheeltec-record ") + kVersion;
  return settings;
}

}  // namespace wheeltec::record
