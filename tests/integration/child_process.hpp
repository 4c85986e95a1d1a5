#pragma once

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace integration {

// How a child process ended.
struct ExitStatus {
  bool exited = false;  // by exit(); otherwise killed by `signal`
  int code = -1;
  int signal = 0;
  bool exited_with(int expected) const { return exited && code == expected; }
  std::string describe() const;
};

// A program started with fork/exec, stdin from /dev/null and stdout/stderr in files
// of `output_dir` named after it. The destructor kills and reaps it if still running.
class ChildProcess {
 public:
  using Environment = std::vector<std::pair<std::string, std::string>>;

  ChildProcess(std::string name, const std::filesystem::path& program, const std::vector<std::string>& arguments,
               const std::filesystem::path& output_dir, const Environment& extra_environment = {});
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  const std::string& name() const { return name_; }
  pid_t pid() const { return pid_; }
  bool running();
  void send_signal(int signal);

  // Waits until the process ends; empty if it is still running after `timeout`.
  std::optional<ExitStatus> wait_for_exit(std::chrono::milliseconds timeout);
  // SIGTERM, then SIGKILL if it has not ended after `grace`.
  ExitStatus terminate(std::chrono::milliseconds grace = std::chrono::seconds(3));
  ExitStatus kill();

  std::string standard_output() const;
  std::string standard_error() const;
  // Both outputs, labelled, for failure messages.
  std::string output_report() const;

 private:
  std::string name_;
  std::filesystem::path stdout_path_;
  std::filesystem::path stderr_path_;
  pid_t pid_ = -1;
  int pidfd_ = -1;
  std::optional<ExitStatus> exit_status_;
};

// Runs a program to completion (killing it after `timeout`) and returns how it ended
// together with what it printed.
struct CompletedProcess {
  ExitStatus status;
  std::string out;
  std::string err;
  bool timed_out = false;
  std::string describe() const;
};

CompletedProcess run_program(const std::filesystem::path& program, const std::vector<std::string>& arguments,
                             const std::filesystem::path& output_dir,
                             std::chrono::milliseconds timeout = std::chrono::seconds(10),
                             const ChildProcess::Environment& extra_environment = {});

}  // namespace integration
