#include "dock_player.hpp"

#include <chrono>

#include "can_bus.hpp"
#include "test_environment.hpp"
#include "wheeltec/frames/charging_dock.hpp"

namespace ros2_tests {

DockPlayer::DockPlayer(bool charging) : charging_(charging), thread_([this] { run(); }) {}

DockPlayer::~DockPlayer() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void DockPlayer::set_charging(bool charging) {
  {
    std::lock_guard lock(mutex_);
    charging_ = charging;
    changed_ = true;
  }
  wake_.notify_all();
}

void DockPlayer::run() {
  constexpr auto kReportPeriod = std::chrono::milliseconds(100);
  integration::CanBus bus(integration::test_interface());
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wheeltec::ChargingDockState state;
    state.charging = charging_;
    state.ir = {false, true, true, false};  // facing away from the dock, on it
    changed_ = false;
    lock.unlock();
    bus.send(wheeltec::encode_charging_dock_frame(state));
    lock.lock();
    wake_.wait_for(lock, kReportPeriod, [&] { return stopping_ || changed_; });
  }
}

}  // namespace ros2_tests
