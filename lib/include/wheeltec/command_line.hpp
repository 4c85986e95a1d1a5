#pragma once

// What the command lines of wheeltecd, wheeltecctl and wheeltec-emu share (CLI11,
// header-only; each program links CLI11): the --version flag and number checks.

#include <cmath>
#include <limits>
#include <string>

#include <CLI/CLI.hpp>

#include "wheeltec/version.hpp"

namespace wheeltec::command_line {

// --version prints "NAME VERSION" to stdout, as -h/--help prints the help; both exit 0
// through CLI::App::exit.
inline void add_version_flag(CLI::App& app) {
  app.set_version_flag("--version", app.get_name() + " " + kVersion, "Print the version and exit");
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
