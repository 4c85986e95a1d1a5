#pragma once

#include <stdexcept>
#include <string>

namespace wheeltecctl {

// Process exit codes (spec section 1 and 3).
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitUnreachable = 3;

// A failure that ends the program: `what()` is the one-line message printed after
// "wheeltecctl: ", `exit_code()` the status the process exits with.
class CliError : public std::runtime_error {
 public:
  CliError(int exit_code, const std::string& message)
      : std::runtime_error(message), exit_code_(exit_code) {}
  int exit_code() const noexcept { return exit_code_; }

 private:
  int exit_code_;
};

}  // namespace wheeltecctl
