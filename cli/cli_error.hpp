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

// The daemon answered a request with a JSON-RPC error object.
class RpcError : public CliError {
 public:
  RpcError(const std::string& method, int code, const std::string& message)
      : CliError(kExitFailure, method + ": " + message + " (code " + std::to_string(code) + ")"),
        method_(method),
        code_(code),
        daemon_message_(message) {}
  const std::string& method() const noexcept { return method_; }
  int code() const noexcept { return code_; }
  const std::string& daemon_message() const noexcept { return daemon_message_; }

 private:
  std::string method_;
  int code_;
  std::string daemon_message_;
};

}  // namespace wheeltecctl
