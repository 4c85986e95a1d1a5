#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace bench {

// A program under measurement (wheeltecd, the floor relay, cangen): started with
// fork/exec, output to files in `log_dir`, terminated and reaped by the destructor.
class ChildProgram {
 public:
  ChildProgram(const std::string& name, const std::vector<std::string>& argv, const std::filesystem::path& log_dir);
  ~ChildProgram();
  ChildProgram(const ChildProgram&) = delete;
  ChildProgram& operator=(const ChildProgram&) = delete;

  pid_t pid() const { return pid_; }
  bool running();
  // Waits (up to timeout_s) until a Unix stream socket at `path` accepts connections.
  void wait_for_socket(const std::filesystem::path& path, int timeout_s = 5);
  void terminate();
  std::string log_tail() const;

 private:
  std::string name_;
  std::filesystem::path log_path_;
  pid_t pid_ = -1;
};

}  // namespace bench
