#include "gateway.hpp"

#include <unistd.h>

#include <csignal>
#include <memory>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "wheeltec/rpc.hpp"
#include "wheeltec/seconds.hpp"
#include "wheeltec/telemetry_json.hpp"
#include "wheeltec/version.hpp"

#include "link_info.hpp"
#include "wheeltec/service/logging.hpp"
#include "stats_report.hpp"

namespace wheeltec::daemon {
namespace {

}  // namespace

Gateway::Gateway(boost::asio::io_context& io, Options options, GatewayConfig config, AccessConfig access)
    : io_(io),
      options_(std::move(options)),
      config_(std::move(config)),
      started_(std::chrono::steady_clock::now()),
      link_(io, config_.can.interface),
      chassis_(io, from_seconds<std::chrono::nanoseconds>(config_.telemetry.timeout_s), config_.telemetry.low_battery_v),
      dock_(io),
      control_io_(io, link_, config_.control.rate_hz),
      control_(control_io_.ports(), config_),
      rpc_(control_, chassis_, config_.chassis.type, api_counters_, [this] { return status_json(); },
           [this] { return stats_json(); }),
      api_(io, config_.api, access.socket_group, std::move(access.control_policy), rpc_, api_counters_),
      signals_(io, SIGINT, SIGTERM, SIGHUP),
      notifier_(io) {}

void Gateway::start() {
  link_.on_frame([this](const asio_can::ReceivedFrame& received) {
    if (!dock_.feed(received.frame)) chassis_.feed(received.frame, received.time);
  });
  link_.on_batch_handled([this] { api_.send_queued(); });
  link_.on_state([this](BusState state) { on_bus_state(state); });
  chassis_.on_sample([this](const TelemetrySample& sample) { on_sample(sample); });
  chassis_.on_online([this](bool online) { on_online(online); });
  chassis_.on_stage([this](auto previous, auto stage) { on_stage(previous, stage); });
  dock_.on_change([this] { status_may_have_changed(); });
  control_.on_change([this] { status_may_have_changed(); });
  api_.on_client_gone([this](ClientId id) {
    if (!stopping_) control_.client_gone(id);
    if (notifier_.active()) notifier_.status(status_line());
  });

  spdlog::info("wheeltecd {} starting: interface {}, dialect {}, chassis {}", kVersion, config_.can.interface,
               to_string(config_.can.dialect), to_string(config_.chassis.type));
  bus_state_ = link_.state();
  last_status_ = status_fields();
  wait_for_signal();
  api_.start();
  link_.start();
  // A link that came up was checked already (on_bus_state); a down one may still say its bitrate.
  if (link_.state() != BusState::up) check_link_bitrate(config_.can.interface, config_.can.bitrate);
  control_.start();
  notifier_.start([this] { return status_line(); });
  notifier_.ready();
}

void Gateway::on_bus_state(BusState state) {
  const BusState previous = bus_state_;
  bus_state_ = state;
  if (state == BusState::down) chassis_.link_lost();
  if (state == BusState::up && previous != BusState::up) {
    control_.link_came_up();
    check_link_bitrate(config_.can.interface, config_.can.bitrate);
  }
  status_may_have_changed();
}

void Gateway::on_sample(const TelemetrySample& sample) {
  api_.queue_telemetry(sample);
  check_command_response(sample);
  status_may_have_changed();
}

void Gateway::on_online(bool online) {
  if (online) control_.chassis_came_online();
  if (!online) command_response_.reset();
  status_may_have_changed();
}

void Gateway::on_stage(std::optional<ChassisStage> previous, std::optional<ChassisStage> stage) {
  if (!stage) {
    spdlog::info("chassis phase unknown: offline");
    return;
  }
  switch (*stage) {
    case ChassisStage::booting:
      if (previous) {
        spdlog::warn("chassis controller rebooted (flag_stop set after a telemetry gap): booting");
      } else {
        spdlog::info("chassis phase booting (flag_stop set)");
      }
      break;
    case ChassisStage::self_test_awaited:
      spdlog::info("chassis phase self-test: boot over, watching for the controller's own drive");
      break;
    case ChassisStage::self_test_driving:
      spdlog::warn("chassis self-test: the controller drives forward by itself (2 s at 0.2 m/s, about 0.4 m)");
      break;
    case ChassisStage::ready:
      spdlog::info("chassis phase ready");
      break;
    case ChassisStage::halted:
      spdlog::warn("chassis halted: flag_stop set outside boot (enable switch off, low voltage or a protection)");
      break;
  }
  // The firmware stores a command received now and runs it after its self-test: nothing
  // but zero may be left standing.
  const ChassisPhase phase = phase_of(*stage);
  if (phase == ChassisPhase::booting || phase == ChassisPhase::self_test) {
    if (control_.owner() || control_.target() != Velocity{}) {
      spdlog::warn("chassis {}: target zeroed and control released", to_string(phase));
    }
    control_.stop();
  }
}

void Gateway::check_command_response(const TelemetrySample& sample) {
  const CommandResponse before = command_response_.state();
  const CommandResponse now = command_response_.update(control_.target(), sample.record.stopped,
                                                       sample.record.velocity, sample.time);
  if (now == before) return;
  if (now == CommandResponse::ignored) {
    spdlog::warn("the chassis ignores the drive commands: no motion after {:g} s of commanding it with flag_stop clear; "
                 "likely cause: can.dialect ({}) does not match the firmware (try the other dialect)",
                 std::chrono::duration<double>(CommandResponseMonitor::kPatience).count(),
                 to_string(config_.can.dialect));
  } else if (before == CommandResponse::ignored) {
    spdlog::info("the chassis {}", now == CommandResponse::followed ? "follows the commands again" : "is no longer commanded to move");
  }
}

void Gateway::status_may_have_changed() {
  StatusFields fields = status_fields();
  if (fields == last_status_) return;
  last_status_ = fields;
  if (notifier_.active()) notifier_.status(status_line());
  if (!api_.has_status_subscribers()) return;
  api_.publish_status(
      std::make_shared<const std::string>(rpc::encode_notification(rpc::kTopicStatus, status_json())));
}

StatusFields Gateway::status_fields() const {
  StatusFields fields;
  fields.bus_state = link_.state();
  fields.online = chassis_.online();
  if (const auto& latest = chassis_.latest()) {
    fields.stopped = latest->record.stopped;
    fields.battery_v = round_battery_v(latest->record.battery_v);
    fields.battery_low = latest->battery_low;
  }
  fields.phase = chassis_.phase();
  fields.commands_ignored = command_response_.commands_ignored();
  if (const auto& dock = dock_.report()) fields.dock = DockStatus{dock->charging, dock->ir};
  fields.control_enabled = control_.enabled();
  fields.owner = control_.owner();
  fields.target = control_.target();
  return fields;
}

std::string Gateway::status_line() const {
  std::string line = fmt::format("bus {}, chassis {}", to_string(last_status_.bus_state),
                                 last_status_.online ? "online" : "offline");
  if (last_status_.battery_v) line += fmt::format(", battery {:.2f} V", *last_status_.battery_v);
  line += fmt::format(", {} client{}", api_counters_.clients, api_counters_.clients == 1 ? "" : "s");
  if (last_status_.control_enabled) line += ", control enabled";
  return line;
}

nlohmann::json Gateway::status_json() const {
  const StatusIdentity identity{config_.can.interface, config_.chassis.type, config_.can.dialect};
  return status_to_json(identity, status_fields(), uptime_s(), chassis_.telemetry_age_s());
}

nlohmann::json Gateway::stats_json() const {
  return stats_to_json(link_.counters(), chassis_.counters(), api_counters_, uptime_s());
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
  link_.stop();
  boost::system::error_code ignored;
  signals_.cancel(ignored);
  io_.stop();
}

// Only what can change while running is taken over; the rest needs a restart.
void Gateway::reload() {
  const auto file = config_file_to_load(options_);
  spdlog::info("SIGHUP: reloading the configuration{}{}", file ? " from " : " (no config file)", file.value_or(""));
  GatewayConfig fresh;
  std::optional<AccessConfig> access;
  try {
    fresh = load_config(options_);
    access.emplace(resolve_access(fresh.api, ::geteuid()));
  } catch (const ConfigError& error) {
    spdlog::error("SIGHUP: {}; keeping the running configuration", error.what());
    return;
  }

  const auto keep = [&](auto& fresh_value, const auto& running_value, const char* key) {
    if (fresh_value != running_value) spdlog::warn("SIGHUP: {} changed; it takes effect after a restart", key);
    fresh_value = running_value;
  };
  keep(fresh.can.interface, config_.can.interface, "can.interface");
  keep(fresh.can.dialect, config_.can.dialect, "can.dialect");
  keep(fresh.can.bitrate, config_.can.bitrate, "can.bitrate");
  keep(fresh.chassis.type, config_.chassis.type, "chassis.type");
  keep(fresh.chassis.ackermann_z, config_.chassis.ackermann_z, "chassis.ackermann_z");
  keep(fresh.api.socket, config_.api.socket, "api.socket");
  keep(fresh.api.mode, config_.api.mode, "api.mode");
  keep(fresh.api.group, config_.api.group, "api.group");

  config_ = std::move(fresh);
  service::set_log_level(config_.log.level);
  control_.apply(config_);
  chassis_.set_timeout(from_seconds<std::chrono::nanoseconds>(config_.telemetry.timeout_s));
  chassis_.set_low_battery_v(config_.telemetry.low_battery_v);
  api_.set_policy(std::move(access->control_policy));
  api_.set_max_clients(config_.api.max_clients);
  spdlog::info("SIGHUP: configuration reloaded");
  status_may_have_changed();
}

}  // namespace wheeltec::daemon
