#pragma once

// wheeltec-emu --serial on a pseudo-terminal with wheeltecd --serial in front of it: the
// fixture of the suites that drive the emulated controller end to end.

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "serial_daemon.hpp"

namespace serial_tests {

// Not SerialTest: the emulator, not the fake controller, holds the pseudo-terminal.
class EmulatorOnPty : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::make_unique<integration::TestDirectory>();
    link_ = directory_->path() / "wheeltec_controller";
  }
  void TearDown() override {
    daemon_.reset();
    if (emulator_) emulator_->kill();
    emulator_.reset();
    directory_.reset();
  }

  void start_emulator(const std::vector<std::string>& extra = {}) {
    std::vector<std::string> arguments{"--serial", link_.string(), "--boot-delay", "1", "--no-self-test"};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    emulator_ = std::make_unique<ChildProcess>("wheeltec-emu", integration::program_path("wheeltec-emu"), arguments,
                                               directory_->path());
    started_ = SteadyClock::now();
    // It publishes the link once its pseudo-terminal is ready.
    const auto deadline = SteadyClock::now() + 5s + integration::start_allowance();
    struct stat info {};
    while (::stat(link_.c_str(), &info) != 0 || !S_ISCHR(info.st_mode)) {
      if (auto ended = emulator_->wait_for_exit(0ms)) FAIL() << "wheeltec-emu ended: " << ended->describe() << "\n" << logs();
      if (SteadyClock::now() > deadline) FAIL() << "wheeltec-emu did not publish " << link_ << " within 5 s\n" << logs();
      std::this_thread::sleep_for(10ms);
    }
  }

  SerialDaemon& start_daemon(DaemonOptions options = {}) {
    daemon_ = std::make_unique<SerialDaemon>(directory_->path(), link_, std::move(options));
    daemon_->wait_listening();
    return *daemon_;
  }

  std::string logs() const {
    std::string text;
    if (daemon_) text += daemon_->logs();
    if (emulator_) text += emulator_->output_report();
    return text;
  }

  std::unique_ptr<integration::TestDirectory> directory_;
  std::filesystem::path link_;
  std::unique_ptr<ChildProcess> emulator_;
  std::unique_ptr<SerialDaemon> daemon_;
  SteadyClock::time_point started_;
};

}  // namespace serial_tests
