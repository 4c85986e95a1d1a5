#pragma once

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>

#include "child_program.hpp"

namespace bench {

// Exact counts of what a process does over a window, independent of the kernel's
// tick-sampled CPU time (which in User-Mode Linux is charged in whole 10 ms ticks).

// The system calls of a running process (and its threads): `strace -c -f -p PID` attached
// from construction until stop().
class SyscallCount {
 public:
  SyscallCount(const std::string& strace, pid_t pid, const std::filesystem::path& dir, const std::string& name);
  // Detaches strace and returns the calls per system call name (key "total": all of them).
  std::map<std::string, std::uint64_t> stop();

 private:
  std::filesystem::path output_;
  std::unique_ptr<ChildProgram> strace_;
};

// Instructions executed in user space by a program running under
// `valgrind --tool=callgrind`: each dump() asks it (through callgrind_control) to write
// its counts since the previous dump and returns their total.
class CallgrindCounter {
 public:
  CallgrindCounter(std::string callgrind_control, pid_t pid, std::filesystem::path out_file)
      : control_(std::move(callgrind_control)), pid_(pid), out_file_(std::move(out_file)) {}
  std::uint64_t dump();

 private:
  std::string control_;
  pid_t pid_;
  std::filesystem::path out_file_;
  int dumps_ = 0;
};

}  // namespace bench
