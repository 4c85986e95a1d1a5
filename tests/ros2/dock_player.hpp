#pragma once

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace ros2_tests {

// A WHEELTEC auto-recharge dock on vcan0: its report (0x182) ten times a second, as the
// real dock sends it, charging or not, until destroyed. The daemon hears the dock from the
// first report and forgets it 3 s after the last.
class DockPlayer {
 public:
  explicit DockPlayer(bool charging);
  ~DockPlayer();
  DockPlayer(const DockPlayer&) = delete;
  DockPlayer& operator=(const DockPlayer&) = delete;

  // From the next report on, which goes out at once.
  void set_charging(bool charging);

 private:
  void run();

  std::mutex mutex_;
  std::condition_variable wake_;
  bool charging_;
  bool changed_ = false;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace ros2_tests
