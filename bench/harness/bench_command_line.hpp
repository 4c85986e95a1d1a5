#pragma once

// A benchmark's command line (CLI11) with its own usage text: printed to stdout by -h/--help
// (exit 0), and after a usage error to stderr with the error (exit 2).

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

namespace bench {

class BenchCommandLine {
 public:
  BenchCommandLine(std::string name, std::string usage);
  CLI::App& app() { return app_; }
  template <typename T>
  CLI::Option* value(const std::string& flag, T& into) {
    return app_.add_option(flag, into);
  }
  CLI::Option* flag(const std::string& flag, bool& into) { return app_.add_flag(flag, into); }
  bool given(const std::string& flag) const { return app_.count(flag) > 0; }
  // Exits after --help; throws std::invalid_argument on a usage error.
  void parse(int argc, char** argv);
  const std::string& name() const { return name_; }
  const std::string& usage() const { return usage_; }

 private:
  std::string name_, usage_;
  CLI::App app_;
};

// The benchmark's main(): `body` parses the command line and measures. A usage error
// (std::invalid_argument) prints the error and the usage and returns 2; any other exception
// its message and 1.
int run_main(const BenchCommandLine& command_line, const std::function<int()>& body);

}  // namespace bench
