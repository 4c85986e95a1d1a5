#include "gateway.hpp"

#include <csignal>
#include <memory>
#include <utility>

#include <spdlog/spdlog.h>

#include "wheeltec/api/rpc.hpp"
#include "wheeltec/service/logging.hpp"
#include "wheeltec/version.hpp"

#include "link/can_chassis_link.hpp"
#include "config_reload.hpp"
#include "link/serial_chassis_link.hpp"
#include "api/stats_report.hpp"

namespace wheeltec::daemon {
namespace {

LinkState link_state_of(BusState state) { return state == BusState::down ? LinkState::down : LinkState::up; }

std::unique_ptr<ChassisLink> make_link(boost::asio::io_context& io, const GatewayConfig& config) {
  if (config.transport == Transport::serial) return std::make_unique<SerialChassisLink>(io, config);
  return std::make_unique<CanChassisLink>(io, config);
}

}  // namespace

Gateway::Gateway(boost::asio::io_context& io, Options options, GatewayConfig config, AccessConfig access)
    : io_(io),
      options_(std::move(options)),
      config_(std::move(config)),
      started_(std::chrono::steady_clock::now()),
      link_(make_link(io, config_)),
      telemetry_(config_.telemetry.low_battery_v, config_.odometry.scale),
      supervisor_(supervisor_settings(config_)),
      dock_(io),
      control_io_(io, *link_, config_),
      control_(control_io_.ports(), supervisor_, config_, events_),
      rpc_(control_, telemetry_, config_.chassis.type, config_.transport, api_counters_, events_,
           [this] { return status_json(); }, [this] { return stats_json(); }),
      api_(io, config_.api, access.socket_group, std::move(access.control_policy), rpc_, api_counters_, events_),
      signals_(io, SIGINT, SIGTERM, SIGHUP),
      notifier_(io) {
  events_.deliver_to(api_);
  supervisor_.restore(control_io_.latch_file().load(std::chrono::system_clock::now()));
}

void Gateway::start() {
  dock_.on_change([this] { status_may_have_changed(); });
  control_.on_change([this] { status_may_have_changed(); });
  api_.on_client_gone([this](ClientId id) {
    if (!stopping_) control_.client_gone(id);
    if (notifier_.active()) notifier_.status(status_line(last_status_, api_counters_.clients));
  });

  spdlog::info("wheeltecd {} starting: {} {}, chassis {}{}", kVersion, to_string(config_.transport), link_->name(),
               to_string(config_.chassis.type),
               config_.transport == Transport::can ? fmt::format(", dialect {}", to_string(config_.can.dialect)) : "");
  last_status_ = status_fields();
  wait_for_signal();
  api_.start();
  link_->start({
      .record = [this](const RecordBytes& record, RealtimeNanos time) { on_record(record, time); },
      .dock = [this](const ChargingDockState& report) { dock_.heard(report); },
      .state = [this](BusState state) { control_.link_changed(link_state_of(state)); },
      .batch_handled = [this] { api_.send_queued(); },
      .port = [this](int fd) { control_io_.use_port(fd); },
  });
  control_.link_changed(link_state_of(link_->state()));
  control_.start();
  notifier_.start([this] { return status_line(last_status_, api_counters_.clients); });
  notifier_.ready();
}

void Gateway::on_record(const RecordBytes& record, RealtimeNanos time) {
  const TelemetrySample& sample = telemetry_.decode(record, time);
  control_.record(RecordInput{{sample.time, sample.record.stopped, sample.record.velocity},
                              sample.orientation.roll, sample.orientation.pitch});
  api_.queue_telemetry(sample);
  status_may_have_changed();
}

void Gateway::status_may_have_changed() {
  StatusFields fields = status_fields();
  if (fields == last_status_) return;
  last_status_ = fields;
  if (notifier_.active()) notifier_.status(status_line(last_status_, api_counters_.clients));
  if (!api_.has_status_subscribers()) return;
  api_.publish_status(
      std::make_shared<const std::string>(rpc::encode_notification(rpc::kTopicStatus, status_json())));
}

StatusFields Gateway::status_fields() const {
  StatusFields fields;
  fields.bus_state = link_->state();
  if (fields.bus_state == BusState::down) fields.down_cause = link_->down_cause();
  fields.online = supervisor_.online();
  if (const auto& latest = telemetry_.latest()) {
    fields.stopped = latest->record.stopped;
    fields.battery_v = round_battery_v(latest->record.battery_v);
    fields.battery_low = latest->battery_low;
  }
  fields.phase = supervisor_.phase();
  fields.commands_ignored = supervisor_.commands_ignored();
  if (const auto& dock = dock_.report()) fields.dock = DockStatus{dock->charging, dock->ir};
  fields.control_enabled = supervisor_.enabled();
  fields.owner = supervisor_.owner();
  fields.target = supervisor_.target();
  fields.sent = command_velocity(supervisor_.sent());
  fields.limits = config_.control.limits;
  fields.ramp = config_.control.ramp;
  fields.odometry_scale = config_.odometry.scale;
  if (const auto& latch = supervisor_.safety()) fields.latch = LatchMark{latch->source, latch->since};
  return fields;
}

nlohmann::json Gateway::status_json() const {
  const StatusIdentity identity{config_.transport, link_->name(), config_.chassis.type, config_.can.dialect};
  const auto age = supervisor_.telemetry_age(std::chrono::steady_clock::now());
  return status_to_json(identity, status_fields(), uptime_s(),
                        age ? std::optional<double>(std::chrono::duration<double>(*age).count()) : std::nullopt,
                        supervisor_.safety());
}

nlohmann::json Gateway::stats_json() const {
  return stats_to_json(*link_, telemetry_.records(), api_counters_, uptime_s());
}

double Gateway::uptime_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

void Gateway::wait_for_signal() {
  signals_.async_wait([this](const boost::system::error_code& error, int signal_number) {
    if (error) return;
    if (signal_number == SIGHUP) {
      reload();
      wait_for_signal();
    } else {
      shutdown(signal_number);
    }
  });
}

void Gateway::shutdown(int signal_number) {
  spdlog::info("{}: stopping", signal_number == SIGINT ? "SIGINT" : "SIGTERM");
  stopping_ = true;
  notifier_.stopping();
  control_.shutdown();
  api_.close();
  link_->stop();
  boost::system::error_code ignored;
  signals_.cancel(ignored);
  io_.stop();
}

void Gateway::reload() {
  auto outcome = reload_config(options_, config_);
  if (const auto* refused = std::get_if<std::string>(&outcome)) {
    events_.publish(std::nullopt, events::Reload{*refused});
    return;
  }
  auto& reloaded = std::get<ReloadedConfig>(outcome);
  config_ = std::move(reloaded.config);
  service::set_log_level(config_.log.level);
  control_.apply(config_);
  telemetry_.set_low_battery_v(config_.telemetry.low_battery_v);
  telemetry_.set_scale(config_.odometry.scale);
  api_.set_policy(std::move(reloaded.access.control_policy));
  api_.set_max_clients(config_.api.max_clients);
  spdlog::info("SIGHUP: configuration reloaded");
  events_.publish(std::nullopt, events::Reload{});
  status_may_have_changed();
}

}  // namespace wheeltec::daemon
