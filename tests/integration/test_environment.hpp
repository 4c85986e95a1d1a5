#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <string_view>

namespace integration {

// Where the programs under test are: $WHEELTEC_BIN_DIR/NAME when that variable is set,
// else the build locations compiled in by CMake.
std::filesystem::path program_path(std::string_view name);  // "wheeltecd", "wheeltecctl", "wheeltec-emu"

// The CAN interface the tests use ($WHEELTEC_TEST_INTERFACE, default vcan0).
std::string test_interface();

// Extra time a program may take to start ($WHEELTEC_TEST_START_ALLOWANCE_S, default 0):
// for runs with the programs under a checker such as valgrind, which starts slowly.
std::chrono::milliseconds start_allowance();

// A fresh directory under /tmp for one test's files (config, socket, program
// output). Removed at the end unless the test failed, so that its logs can be read.
class TestDirectory {
 public:
  TestDirectory();
  ~TestDirectory();
  TestDirectory(const TestDirectory&) = delete;
  TestDirectory& operator=(const TestDirectory&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(std::string_view name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

}  // namespace integration
