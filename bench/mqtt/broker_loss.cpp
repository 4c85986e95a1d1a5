#include "broker_loss.hpp"

#include <signal.h>

#include <chrono>
#include <memory>
#include <optional>
#include <thread>

#include <fmt/format.h>

#include "latency_stats.hpp"
#include "mqtt_endpoints.hpp"

namespace bench {
namespace {

constexpr int kDrivingWithinS = 20;
constexpr int kFramePerDriveMs = 200;
constexpr int kZeroFrameWithinMs = 2000;

// Publishes drives (a new velocity each, 5 a second) until one reaches the bus; true once
// the bridge drives the robot. The publisher is left connected.
bool drive_until_moving(int broker_port, const std::string& topic, CommandFrames& frames, int& mm,
                        std::unique_ptr<MqttPublisher>& publisher) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(kDrivingWithinS);
  while (std::chrono::steady_clock::now() < deadline) {
    try {
      if (!publisher) publisher = std::make_unique<MqttPublisher>("127.0.0.1", broker_port, "wheeltec-bench-loss");
      mm = 50 + (mm - 49) % 40;  // 50..89 mm/s, never the previous one
      frames.drain();
      publisher->publish(topic, fmt::format(R"({{"vx":{:.3f},"operator":"bench-loss"}})", mm / 1000.0));
      if (frames.first_with(mm, kFramePerDriveMs)) return true;
      publisher->service();
    } catch (const std::exception&) {
      publisher.reset();  // the broker is still starting
      std::this_thread::sleep_for(std::chrono::milliseconds(kFramePerDriveMs));
    }
  }
  return false;
}

void signal_others(const std::vector<BridgeUnderTest>& bridges, std::size_t measured, int signal) {
  for (std::size_t i = 0; i < bridges.size(); ++i) {
    if (i != measured) ::kill(bridges[i].pid, signal);
  }
}

}  // namespace

nlohmann::json LossSeries::to_json() const {
  std::vector<double> us;
  for (const double value : ms) us.push_back(value * 1e3);
  nlohmann::json j = summarize(us).to_json();
  j["missed"] = missed;
  j["never_driving"] = never_driving;
  j["rounds_ms"] = ms;
  return j;
}

std::vector<LossSeries> measure_broker_loss(Broker& broker, CommandFrames& frames,
                                            const std::vector<BridgeUnderTest>& bridges, int rounds) {
  std::vector<LossSeries> series(bridges.size());
  int mm = 50;
  for (int round = 0; round < rounds; ++round) {
    for (std::size_t k = 0; k < bridges.size(); ++k) {
      const std::size_t measured = (k + static_cast<std::size_t>(round)) % bridges.size();
      std::unique_ptr<MqttPublisher> publisher;
      if (!drive_until_moving(broker.port(), bridges[measured].drive_topic, frames, mm, publisher)) {
        ++series[measured].never_driving;
        continue;
      }
      signal_others(bridges, measured, SIGSTOP);
      frames.drain();
      const std::int64_t killed = broker.kill();
      const auto zero = frames.first_with(0, kZeroFrameWithinMs);
      signal_others(bridges, measured, SIGCONT);
      publisher.reset();
      if (zero) series[measured].ms.push_back(static_cast<double>(*zero - killed) / 1e6);
      else ++series[measured].missed;
      broker.restart();
    }
  }
  return series;
}

}  // namespace bench
