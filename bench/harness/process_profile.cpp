#include "process_profile.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <vector>

namespace bench {

namespace {

// Runs a short helper to completion; throws if it fails.
void run_to_completion(const std::vector<std::string>& argv, const std::filesystem::path& log_dir,
                       const std::string& name) {
  ChildProgram helper(name, argv, log_dir);
  for (int i = 0; i < 3000 && helper.running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (helper.running()) throw std::runtime_error(name + " did not finish in 30 s");
}

}  // namespace

SyscallCount::SyscallCount(const std::string& strace, pid_t pid, const std::filesystem::path& dir, const std::string& name)
    : output_(dir / (name + ".strace")) {
  std::filesystem::remove(output_);
  strace_ = std::make_unique<ChildProgram>(
      name + "-strace", std::vector<std::string>{strace, "-c", "-f", "-o", output_.string(), "-p", std::to_string(pid)},
      dir);
  // strace prints "Process N attached" once it has seized the process; until then calls go uncounted.
  const std::filesystem::path log = dir / (name + "-strace.log");
  for (int i = 0; i < 500; ++i) {
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find("attached") != std::string::npos) return;
    if (!strace_->running()) throw std::runtime_error("strace ended: " + strace_->log_tail());
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  throw std::runtime_error("strace did not attach within 5 s");
}

std::map<std::string, std::uint64_t> SyscallCount::stop() {
  strace_->terminate();  // SIGTERM: strace detaches and writes its summary
  std::map<std::string, std::uint64_t> calls;
  std::ifstream in(output_);
  std::string line;
  // Rows: "% time  seconds  usecs/call  calls  [errors]  syscall"; the last is "... total".
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::vector<std::string> fields;
    for (std::string w; words >> w;) fields.push_back(w);
    if (fields.size() < 5 || fields[0].find_first_not_of("0123456789.") != std::string::npos) continue;
    calls[fields.back()] += std::stoull(fields[3]);
  }
  if (calls.empty()) throw std::runtime_error("strace wrote no summary to " + output_.string());
  return calls;
}

std::uint64_t CallgrindCounter::dump() {
  run_to_completion({control_, "-d", std::to_string(pid_)}, out_file_.parent_path(), "callgrind_control");
  const std::filesystem::path file = out_file_.string() + "." + std::to_string(++dumps_);
  for (int i = 0; i < 500 && !std::filesystem::exists(file); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("summary:", 0) == 0) return std::stoull(line.substr(8));
  }
  throw std::runtime_error("no callgrind dump in " + file.string());
}

}  // namespace bench
