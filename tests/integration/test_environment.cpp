#include "test_environment.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <stdexcept>

namespace integration {
namespace {

std::filesystem::path compiled_in_path(std::string_view name) {
  if (name == "wheeltecd") return WHEELTECD_PATH;
  if (name == "wheeltecctl") return WHEELTECCTL_PATH;
  if (name == "wheeltec-emu") return WHEELTEC_EMU_PATH;
  throw std::invalid_argument("unknown program " + std::string(name));
}

}  // namespace

std::filesystem::path program_path(std::string_view name) {
  const char* bin_dir = std::getenv("WHEELTEC_BIN_DIR");
  if (bin_dir != nullptr && *bin_dir != '\0') return std::filesystem::path(bin_dir) / name;
  return compiled_in_path(name);
}

std::string test_interface() {
  const char* name = std::getenv("WHEELTEC_TEST_INTERFACE");
  return name != nullptr && *name != '\0' ? name : "vcan0";
}

std::chrono::milliseconds start_allowance() {
  const char* text = std::getenv("WHEELTEC_TEST_START_ALLOWANCE_S");
  if (text == nullptr || *text == '\0') return std::chrono::milliseconds(0);
  char* end = nullptr;
  const double seconds = std::strtod(text, &end);
  if (*end != '\0' || !(seconds >= 0)) {
    throw std::invalid_argument("WHEELTEC_TEST_START_ALLOWANCE_S must be a number of seconds, not \"" +
                                std::string(text) + "\"");
  }
  return std::chrono::milliseconds(static_cast<long long>(seconds * 1000));
}

TestDirectory::TestDirectory() {
  std::string pattern = "/tmp/wheeltec-it.XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error(std::string("mkdtemp: ") + std::strerror(errno));
  path_ = pattern;
}

TestDirectory::~TestDirectory() {
  const auto* unit_test = ::testing::UnitTest::GetInstance();
  const auto* test = unit_test->current_test_info();
  const auto* suite = unit_test->current_test_suite();
  const bool failed = test != nullptr ? test->result()->Failed() : suite != nullptr && suite->Failed();
  if (failed) {
    std::cerr << "test files kept in " << path_ << "\n";
    return;
  }
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace integration
