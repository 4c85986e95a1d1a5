#pragma once

// What the programs' command lines share (CLI11, header-only; each program links CLI11):
// parsing with one-line usage errors, the --version flag, the --log-level option and
// number checks.

#include <cmath>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <CLI/CLI.hpp>

#include "wheeltec/bridge_flags.hpp"
#include "wheeltec/types.hpp"
#include "wheeltec/version.hpp"

namespace wheeltec::command_line {

// --version prints "NAME VERSION" to stdout, as -h/--help prints the help; both exit 0
// through CLI::App::exit.
inline void add_version_flag(CLI::App& app) {
  app.set_version_flag("--version", app.get_name() + " " + kVersion, "Print the version and exit");
}

// Parses the command line. Empty when the program goes on; else the exit code: 0 after
// --help or --version, 2 after a usage error, which is one line on stderr.
inline std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& done) {
    return app.exit(done);
  } catch (const CLI::ParseError& error) {
    std::cerr << app.get_name() << ": " << error.what() << " (see --help)\n";
    return 2;
  }
  return std::nullopt;
}

// --log-level, one of kLogLevels. `Level` is std::string, or std::optional<std::string>
// where a config file's log.level is the default.
template <typename Level>
CLI::Option* add_log_level_option(CLI::App& app, Level& level,
                                  const std::string& description = "Log level, overrides log.level") {
  const std::vector<std::string> levels(kLogLevels.begin(), kLogLevels.end());
  std::string names;
  for (const auto& name : levels) names += (names.empty() ? "" : "|") + name;
  return app.add_option("--log-level", level, description)
      ->type_name(names)
      ->check(CLI::IsMember(levels).description(""));
}

// --version, --config and --socket, first in --help (parse_bridge_command_line adds --log-level last).
inline void add_bridge_flags(CLI::App& app, BridgeFlags& flags, const std::string& default_config_file) {
  add_version_flag(app);
  app.add_option("--config", flags.config_file, "Config file (JSON); default " + default_config_file + " if it exists")
      ->type_name("FILE");
  app.add_option("--socket", flags.socket, "wheeltecd's socket, overrides socket; default $WHEELTEC_SOCKET, else the "
                                           "daemon's")
      ->type_name("PATH");
}

// A bridge's command line after its own options: --log-level last, then the parse. The
// options, or the exit code as parse() gives it.
template <typename Options>
std::variant<Options, int> parse_bridge_command_line(CLI::App& app, Options& options, int argc, char** argv) {
  add_log_level_option(app, options.log_level);
  if (const std::optional<int> exit_code = parse(app, argc, argv)) return *exit_code;
  return std::move(options);
}

enum class LowBound { inclusive, exclusive };

// A finite number in [low, high], or (low, high]; no high bound by default. Unlike
// CLI::Range it refuses "nan", and its message is short.
inline CLI::Validator finite_in(double low, double high = std::numeric_limits<double>::infinity(),
                                LowBound low_bound = LowBound::inclusive) {
  const std::string range = std::string(low_bound == LowBound::inclusive ? "[" : "(") +
                            CLI::detail::to_string(low) + ", " +
                            (std::isinf(high) ? std::string("inf)") : CLI::detail::to_string(high) + "]");
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value) || !std::isfinite(value)) return "expected a number, got " + text;
        const bool too_low = low_bound == LowBound::inclusive ? value < low : value <= low;
        if (too_low || value > high) return "value " + text + " not in " + range;
        return {};
      },
      range);
}

}  // namespace wheeltec::command_line
