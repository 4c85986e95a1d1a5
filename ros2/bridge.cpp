#include "bridge.hpp"

#include <vector>

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include "wheeltec/service/logging.hpp"

#include "messages.hpp"

namespace wheeltec::ros2 {
namespace {

constexpr auto kDiagnosticsPeriod = std::chrono::seconds(1);
constexpr auto kVoltagePeriod = std::chrono::seconds(1);
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
      diagnostics_timer_(io) {
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
  spdlog::info("ROS 2 topics{} on DDS domain {}{}; daemon at {}", where, config_.domain_id,
               config_.localhost_only ? " (localhost only)" : "", config_.socket);
  cmd_vel_ = std::make_unique<TwistReader>(
      participant_, dds_topic(config_.name_space, "cmd_vel"),
      [this](const geometry_msgs_msg_dds__Twist_& twist) {
        if (cmd_vel_mailbox_.put(twist)) boost::asio::post(io_, [this] { handle_cmd_vel(); });
      });
  daemon_.start();
  run_diagnostics_timer();
}

void Bridge::stop() {
  cmd_vel_.reset();
  driver_.cancel();
  daemon_.stop();
  diagnostics_timer_.cancel();
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
  if (now >= next_voltage_) {
    next_voltage_ = now + kVoltagePeriod;
    const std_msgs_msg_dds__Float32_ voltage{static_cast<float>(record.battery_voltage)};
    publish(voltage_, &voltage, "PowerVoltage");
  }
}

void Bridge::handle_status(const client::Status& status) { status_ = status; }

void Bridge::daemon_down(const client::Subscription::Outage& outage) {
  if (outage.was_up) spdlog::warn("lost wheeltecd at {}: {}", config_.socket, outage.error.message());
  spdlog::debug("reconnecting to wheeltecd in {} ms", outage.retry_in.count());
  status_.reset();
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

void Bridge::run_diagnostics_timer() {
  publish_diagnostics();
  diagnostics_timer_.expires_after(kDiagnosticsPeriod);
  diagnostics_timer_.async_wait([this](boost::system::error_code ec) {
    if (!ec) run_diagnostics_timer();
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

}  // namespace wheeltec::ros2
