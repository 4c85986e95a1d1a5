#include "bridge.hpp"

#include <vector>

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

#include "battery.hpp"
#include "messages.hpp"

namespace wheeltec::ros2 {
namespace {

constexpr auto kOnceASecond = std::chrono::seconds(1);  // diagnostics, robot_charging_flag
constexpr auto kBatteryPeriod = std::chrono::seconds(1);
constexpr int kDepth = 10;
constexpr int kTfDepth = 100;

std::optional<std::string> participant_configuration(const Ros2Config& config) {
  if (!config.localhost_only) return std::nullopt;  // CYCLONEDDS_URI's, or Cyclone's defaults
  std::string configuration = localhost_configuration();
  // The user's own settings still apply, after the localhost ones.
  if (const char* uri = std::getenv("CYCLONEDDS_URI"); uri && *uri) configuration.append(",").append(uri);
  return configuration;
}

// The ROS message of a report; strings point into `report`, `values` holds the key/values.
diagnostic_msgs_msg_dds__DiagnosticStatus_ status_message(const DiagnosticReport& report,
                                                          std::vector<diagnostic_msgs_msg_dds__KeyValue_>& values) {
  values.clear();
  for (const auto& [key, value] : report.values) {
    values.push_back({const_cast<char*>(key.c_str()), const_cast<char*>(value.c_str())});
  }
  diagnostic_msgs_msg_dds__DiagnosticStatus_ status{};
  status.level_ = static_cast<std::uint8_t>(report.level);
  status.name_ = const_cast<char*>(kDiagnosticName);
  status.message_ = const_cast<char*>(report.message.c_str());
  status.hardware_id_ = const_cast<char*>(report.hardware_id.c_str());
  status.values_._length = status.values_._maximum = static_cast<std::uint32_t>(values.size());
  status.values_._buffer = values.data();
  status.values_._release = false;
  return status;
}

}  // namespace

Bridge::Bridge(boost::asio::io_context& io, Ros2Config config)
    : io_(io),
      config_(std::move(config)),
      daemon_(io.get_executor(), config_.socket),
      driver_(io.get_executor(), config_.socket),
      participant_(config_.domain_id, participant_configuration(config_)),
      odom_(participant_, dds_topic(config_.name_space, "odom"), nav_msgs_msg_dds__Odometry__desc, kDepth),
      imu_(participant_, dds_topic(config_.name_space, "imu"), sensor_msgs_msg_dds__Imu__desc, kDepth),
      voltage_(participant_, dds_topic(config_.name_space, "PowerVoltage"), std_msgs_msg_dds__Float32__desc, kDepth),
      diagnostics_(participant_, dds_topic(config_.name_space, "diagnostics"),
                   diagnostic_msgs_msg_dds__DiagnosticArray__desc, kDepth),
      battery_state_(participant_, dds_topic(config_.name_space, "battery_state"),
                     sensor_msgs_msg_dds__BatteryState__desc, kDepth),
      charging_flag_(participant_, dds_topic(config_.name_space, "robot_charging_flag"), std_msgs_msg_dds__Bool__desc,
                     kDepth),
      e_stop_(participant_, dds_topic(config_.name_space, "e_stop"), std_msgs_msg_dds__Bool__desc, 1,
              Durability::transient_local),
      once_a_second_timer_(io) {
  if (config_.publish_tf) {
    tf_.emplace(participant_, dds_topic(config_.name_space, "tf"), tf2_msgs_msg_dds__TFMessage__desc, kTfDepth);
  }
  daemon_.on_telemetry([this](const client::Telemetry& record) { handle_telemetry(record); });
  daemon_.on_status([this](const client::Status& status) { handle_status(status); });
  daemon_.on_up([this] { spdlog::info("connected to wheeltecd at {}", config_.socket); });
  daemon_.on_down([this](const client::Subscription::Outage& outage) { daemon_down(outage); });
}

Bridge::~Bridge() { stop(); }

void Bridge::start() {
  const std::string where = config_.name_space.empty() ? "" : " in namespace /" + config_.name_space;
  spdlog::info("ROS 2 topics{} on DDS domain {}{}; daemon at {}; cmd_vel is {}", where, config_.domain_id,
               config_.localhost_only ? " (localhost only)" : "", config_.socket,
               config_.cmd_vel_stamped ? "TwistStamped" : "Twist");
  if (config_.battery.empty_v.has_value() != config_.battery.full_v.has_value()) {
    spdlog::warn("battery_state has no percentage: battery.{} is not set",
                 config_.battery.empty_v ? "full_v" : "empty_v");
  }
  cmd_vel_ = std::make_unique<CmdVelReader>(
      participant_, dds_topic(config_.name_space, "cmd_vel"),
      config_.cmd_vel_stamped ? CmdVelType::twist_stamped : CmdVelType::twist,
      [this](const geometry_msgs_msg_dds__Twist_& twist) {
        if (cmd_vel_mailbox_.put(twist)) boost::asio::post(io_, [this] { handle_cmd_vel(); });
      });
  e_stop_trigger_ = std::make_unique<EmptyReader>(participant_, dds_topic(config_.name_space, "e_stop_trigger"), [this] {
    request(e_stop_trigger_pending_, &Bridge::handle_e_stop_trigger);
  });
  if (config_.allow_e_stop_reset) {
    e_stop_reset_ = std::make_unique<EmptyReader>(participant_, dds_topic(config_.name_space, "e_stop_reset"), [this] {
      request(e_stop_reset_pending_, &Bridge::handle_e_stop_reset);
    });
    spdlog::warn("e_stop_reset is subscribed: anyone on DDS domain {} can release the emergency stop",
                 config_.domain_id);
  }
  daemon_.start();
  run_once_a_second_timer();
}

void Bridge::stop() {
  cmd_vel_.reset();
  e_stop_trigger_.reset();
  e_stop_reset_.reset();
  driver_.cancel();
  daemon_.stop();
  once_a_second_timer_.cancel();
}

// --- out: the daemon's records and status ---

void Bridge::publish(DdsWriter& writer, const void* sample, const char* topic) {
  if (writer.write(sample)) return;
  if (!write_failure_logged_) spdlog::warn("publishing {} failed: {}", topic, writer.error());
  write_failure_logged_ = true;
}

void Bridge::handle_telemetry(const client::Telemetry& record) {
  const nav_msgs_msg_dds__Odometry_ odometry = odometry_of(record, config_.frames, config_.covariance);
  publish(odom_, &odometry, "odom");
  const sensor_msgs_msg_dds__Imu_ imu = imu_of(record, config_.frames, config_.covariance);
  publish(imu_, &imu, "imu");
  if (tf_) {
    const OdomTransform transform(record, config_.frames);
    publish(*tf_, &transform.message, "tf");
  }
  const Clock::time_point now = Clock::now();
  if (now >= next_battery_) {
    next_battery_ = now + kBatteryPeriod;
    const std_msgs_msg_dds__Float32_ voltage{static_cast<float>(record.battery_voltage)};
    publish(voltage_, &voltage, "PowerVoltage");
    const sensor_msgs_msg_dds__BatteryState_ battery =
        battery_state_of(record, dock_charging().value_or(false), config_.frames, config_.battery);
    publish(battery_state_, &battery, "battery_state");
  }
}

void Bridge::handle_status(const client::Status& status) {
  status_ = status;
  if (const std::optional<bool> latched = e_stop_publication_.on_status(e_stop_of(status))) publish_e_stop(*latched);
  // A dock that appears, or starts or stops charging, is told at once; the timer repeats it.
  if (const std::optional<bool> charging = dock_charging(); charging != charging_flag_sent_) publish_charging_flag();
}

std::optional<bool> Bridge::dock_charging() const {
  if (!status_) return std::nullopt;
  const std::optional<Dock> dock = dock_of(*status_);
  if (!dock) return std::nullopt;
  return dock->charging;
}

void Bridge::daemon_down(const client::Subscription::Outage& outage) {
  if (outage.was_up) spdlog::warn("lost wheeltecd at {}: {}", config_.socket, outage.error.message());
  spdlog::debug("reconnecting to wheeltecd in {} ms", outage.retry_in.count());
  status_.reset();
  charging_flag_sent_.reset();
}

void Bridge::publish_diagnostics() {
  const DiagnosticReport report = diagnose(status_, refusals_.shown(Clock::now()), counters_);
  std::vector<diagnostic_msgs_msg_dds__KeyValue_> values;
  diagnostic_msgs_msg_dds__DiagnosticStatus_ status = status_message(report, values);
  diagnostic_msgs_msg_dds__DiagnosticArray_ array{};
  const auto since_epoch = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch());
  array.header_.stamp_ = stamp_of(since_epoch.count());
  array.header_.frame_id_ = const_cast<char*>("");
  array.status_._length = array.status_._maximum = 1;
  array.status_._buffer = &status;
  array.status_._release = false;
  publish(diagnostics_, &array, "diagnostics");
}

// robot_charging_flag, as the vendor's driver: only while a dock is heard.
void Bridge::publish_charging_flag() {
  charging_flag_sent_ = dock_charging();
  if (!charging_flag_sent_) return;
  const std_msgs_msg_dds__Bool_ flag{*charging_flag_sent_};
  publish(charging_flag_, &flag, "robot_charging_flag");
}

void Bridge::run_once_a_second_timer() {
  publish_diagnostics();
  publish_charging_flag();
  once_a_second_timer_.expires_after(kOnceASecond);
  once_a_second_timer_.async_wait([this](boost::system::error_code ec) {
    if (!ec) run_once_a_second_timer();
  });
}

// --- in: cmd_vel ---

void Bridge::handle_cmd_vel() {
  const TwistMailbox::Mail mail = cmd_vel_mailbox_.take();
  if (!cmd_vel_) return;  // stopped
  counters_.cmd_vel_received += mail.received;
  if (mail.non_finite > 0 && counters_.cmd_vel_dropped_non_finite == 0) {
    spdlog::warn("cmd_vel with a non-finite value dropped (counted in diagnostics from now on)");
  }
  counters_.cmd_vel_dropped_non_finite += mail.non_finite;
  if (!mail.drive) return;
  driver_.drive(*mail.drive, [this](boost::system::error_code ec, const client::Json& result) {
    if (ec != boost::asio::error::operation_aborted) drive_answered(ec, result);
  });
}

void Bridge::drive_answered(boost::system::error_code ec, const client::Json& result) {
  if (!ec) return;
  ++counters_.drives_refused;
  std::string message;
  if (ec.category() == client::rpc_category()) {
    message = fmt::format("{} ({})", result.value("message", ec.message()), result.value("code", 0));
  } else {
    message = "wheeltecd: " + ec.message();
  }
  service::log_limited(refusal_log_, spdlog::level::warn, "cmd_vel refused: {}", message);
  refusals_.note(Clock::now(), std::move(message));
}

// --- the emergency stop ---

void Bridge::publish_e_stop(bool latched) {
  const std_msgs_msg_dds__Bool_ flag{latched};
  publish(e_stop_, &flag, "e_stop");
  spdlog::info("e_stop: {}", latched ? "latched" : "not latched");
}

void Bridge::request(std::atomic<bool>& pending, void (Bridge::*handler)()) {
  if (pending.exchange(true)) return;
  boost::asio::post(io_, [this, &pending, handler] {
    pending = false;
    (this->*handler)();
  });
}

void Bridge::handle_e_stop_trigger() {
  if (!e_stop_trigger_) return;  // stopped
  spdlog::warn("e_stop_trigger: latching the emergency stop");
  daemon_.async_call("estop", client::Json{{"reason", "ros2"}}, [this](boost::system::error_code ec,
                                                                      const client::Json& result) {
    if (!ec || ec == boost::asio::error::operation_aborted) return;
    const std::string why = ec.category() == client::rpc_category() ? result.value("message", ec.message())
                                                                     : "wheeltecd: " + ec.message();
    service::log_limited(e_stop_log_, spdlog::level::err, "e_stop_trigger: estop failed: {}", why);
  });
}

void Bridge::handle_e_stop_reset() {
  if (!e_stop_reset_) return;  // stopped
  spdlog::info("e_stop_reset: releasing the emergency stop");
  daemon_.async_call("release", nullptr, [this](boost::system::error_code ec, const client::Json& result) {
    if (!ec || ec == boost::asio::error::operation_aborted) return;
    const std::string why = ec.category() == client::rpc_category()
                                ? fmt::format("{} ({})", result.value("message", ec.message()), result.value("code", 0))
                                : "wheeltecd: " + ec.message();
    service::log_limited(e_stop_log_, spdlog::level::warn, "e_stop_reset: release refused: {}", why);
  });
}

}  // namespace wheeltec::ros2
