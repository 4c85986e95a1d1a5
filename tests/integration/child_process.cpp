#include "child_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace integration {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

ExitStatus decode_wait_status(int status) {
  ExitStatus out;
  if (WIFEXITED(status)) {
    out.exited = true;
    out.code = WEXITSTATUS(status);
  } else if (WIFSIGNALED(status)) {
    out.signal = WTERMSIG(status);
  }
  return out;
}

[[noreturn]] void exec_child(const std::filesystem::path& program, const std::vector<std::string>& arguments,
                             const std::filesystem::path& stdout_path, const std::filesystem::path& stderr_path,
                             const ChildProcess::Environment& extra_environment) {
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  const int out_fd = ::open(stdout_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int err_fd = ::open(stderr_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (null_fd < 0 || out_fd < 0 || err_fd < 0) ::_exit(126);
  ::dup2(null_fd, STDIN_FILENO);
  ::dup2(out_fd, STDOUT_FILENO);
  ::dup2(err_fd, STDERR_FILENO);
  // The test runner may block or ignore signals; the child must start with defaults.
  sigset_t none;
  sigemptyset(&none);
  ::sigprocmask(SIG_SETMASK, &none, nullptr);
  ::signal(SIGPIPE, SIG_DFL);
  for (const auto& [key, value] : extra_environment) {
    if (value.empty()) {
      ::unsetenv(key.c_str());
    } else {
      ::setenv(key.c_str(), value.c_str(), 1);
    }
  }
  std::vector<char*> argv;
  std::string program_text = program.string();
  argv.push_back(program_text.data());
  std::vector<std::string> copies = arguments;
  for (auto& argument : copies) argv.push_back(argument.data());
  argv.push_back(nullptr);
  ::execv(program_text.c_str(), argv.data());
  const std::string message = "exec " + program_text + ": " + std::strerror(errno) + "\n";
  [[maybe_unused]] auto ignored = ::write(STDERR_FILENO, message.data(), message.size());
  ::_exit(127);
}

}  // namespace

std::string ExitStatus::describe() const {
  if (exited) return "exit code " + std::to_string(code);
  if (signal != 0) return std::string("killed by signal ") + ::strsignal(signal);
  return "unknown end";
}

ChildProcess::ChildProcess(std::string name, const std::filesystem::path& program,
                           const std::vector<std::string>& arguments, const std::filesystem::path& output_dir,
                           const Environment& extra_environment)
    : name_(std::move(name)),
      stdout_path_(output_dir / (name_ + ".stdout")),
      stderr_path_(output_dir / (name_ + ".stderr")) {
  if (!std::filesystem::exists(program)) throw std::runtime_error(name_ + ": program not found: " + program.string());
  pid_ = ::fork();
  if (pid_ < 0) throw std::runtime_error(name_ + ": fork: " + std::strerror(errno));
  if (pid_ == 0) exec_child(program, arguments, stdout_path_, stderr_path_, extra_environment);
  pidfd_ = static_cast<int>(::syscall(SYS_pidfd_open, pid_, 0));
  if (pidfd_ < 0) {
    const int error = errno;
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    throw std::runtime_error(name_ + ": pidfd_open: " + std::strerror(error));
  }
}

ChildProcess::~ChildProcess() {
  if (!exit_status_) kill();
  if (pidfd_ >= 0) ::close(pidfd_);
}

bool ChildProcess::running() { return !wait_for_exit(std::chrono::milliseconds(0)).has_value(); }

void ChildProcess::send_signal(int signal) {
  if (!exit_status_) ::kill(pid_, signal);
}

std::optional<ExitStatus> ChildProcess::wait_for_exit(std::chrono::milliseconds timeout) {
  if (exit_status_) return exit_status_;
  pollfd ready{pidfd_, POLLIN, 0};
  int polled;
  do {
    polled = ::poll(&ready, 1, static_cast<int>(timeout.count()));
  } while (polled < 0 && errno == EINTR);
  if (polled <= 0) return std::nullopt;
  int status = 0;
  pid_t reaped;
  do {
    reaped = ::waitpid(pid_, &status, 0);
  } while (reaped < 0 && errno == EINTR);
  if (reaped != pid_) throw std::runtime_error(name_ + ": waitpid: " + std::strerror(errno));
  exit_status_ = decode_wait_status(status);
  return exit_status_;
}

ExitStatus ChildProcess::terminate(std::chrono::milliseconds grace) {
  send_signal(SIGTERM);
  if (auto status = wait_for_exit(grace)) return *status;
  return kill();
}

ExitStatus ChildProcess::kill() {
  send_signal(SIGKILL);
  return *wait_for_exit(std::chrono::hours(1));
}

std::string ChildProcess::standard_output() const { return read_file(stdout_path_); }
std::string ChildProcess::standard_error() const { return read_file(stderr_path_); }

std::string ChildProcess::output_report() const {
  constexpr std::size_t kTail = 6000;
  const auto tail = [](std::string text) {
    return text.size() <= kTail ? text : "[...]\n" + text.substr(text.size() - kTail);
  };
  return "--- " + name_ + " stdout ---\n" + tail(standard_output()) + "--- " + name_ + " stderr ---\n" +
         tail(standard_error()) + "--- end of " + name_ + " ---\n";
}

std::string CompletedProcess::describe() const {
  return (timed_out ? std::string("timed out, ") : std::string()) + status.describe() + "\nstdout:\n" + out +
         "stderr:\n" + err;
}

CompletedProcess run_program(const std::filesystem::path& program, const std::vector<std::string>& arguments,
                             const std::filesystem::path& output_dir, std::chrono::milliseconds timeout,
                             const ChildProcess::Environment& extra_environment) {
  static std::atomic<int> run_number{0};
  const std::string name = program.filename().string() + "-run" + std::to_string(++run_number);
  ChildProcess child(name, program, arguments, output_dir, extra_environment);
  CompletedProcess completed;
  if (auto status = child.wait_for_exit(timeout)) {
    completed.status = *status;
  } else {
    completed.timed_out = true;
    completed.status = child.kill();
  }
  completed.out = child.standard_output();
  completed.err = child.standard_error();
  return completed;
}

}  // namespace integration
