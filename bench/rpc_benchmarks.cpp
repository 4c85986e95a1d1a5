// One request line through parsing and dispatch to its response line.
#include <benchmark/benchmark.h>

#include <chrono>
#include <string>
#include <string_view>
#include <variant>

#include <boost/asio/io_context.hpp>
#include <nlohmann/json.hpp>

#include "wheeltec/config.hpp"
#include "wheeltec/control_frame.hpp"
#include "wheeltec/rpc.hpp"

#include "api_counters.hpp"
#include "can_link.hpp"
#include "can_chassis_link.hpp"
#include "wheeltec/telemetry_decoder.hpp"
#include "client_state.hpp"
#include "control_io.hpp"
#include "control_loop.hpp"
#include "event_fanout.hpp"
#include "rpc_handler.hpp"
#include "status_report.hpp"

namespace {

using namespace wheeltec;
using nlohmann::json;

constexpr std::string_view kDriveLine = R"({"jsonrpc":"2.0","id":17,"method":"drive","params":{"vx":0.25,"vy":-0.1,"wz":0.5}})";
constexpr std::string_view kStatusLine = R"({"jsonrpc":"2.0","id":18,"method":"status"})";

// `drive` from the line to the control frame and the response line: the same library calls
// the daemon's RpcHandler and ControlLoop make. (The daemon's own objects need a CAN link
// that is up, which this host's kernel cannot provide; the end-to-end benchmark covers them.)
void BM_DriveRequestToFrameAndResponse(benchmark::State& state) {
  const VelocityLimits limits;
  for (auto _ : state) {
    auto parsed = rpc::parse_request(kDriveLine);
    const auto& request = std::get<rpc::Request>(parsed);
    auto params = rpc::parse_drive_params(request, ChassisType::mecanum);
    const Velocity& target = std::get<Velocity>(params);
    const ControlCommand command = quantize_command(target, limits);
    CanFrame frame = encode_control_frame(Dialect::manual, command);
    benchmark::DoNotOptimize(frame);
    const Velocity sent = command_velocity(command);
    std::string response = rpc::encode_result(
        request.id, json{{"vx", sent.vx}, {"vy", sent.vy}, {"wz", sent.wz}, {"clamped", command.clamped}});
    benchmark::DoNotOptimize(response.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DriveRequestToFrameAndResponse);

// `status` through the daemon's own RpcHandler (link down: no SocketCAN on this host).
void BM_StatusRequestThroughRpcHandler(benchmark::State& state) {
  boost::asio::io_context io;
  GatewayConfig config;
  config.can.interface = "bench-none";
  daemon::CanChassisLink link(io, config);
  TelemetryDecoder telemetry(config.telemetry.low_battery_v);
  ChassisSupervisor supervisor(daemon::supervisor_settings(config));
  daemon::ControlIo control_io(io, link, config);
  daemon::EventFanout events;  // no subscribers: events cost nothing
  daemon::ControlLoop control(control_io.ports(), supervisor, config, events);
  daemon::ApiCounters counters;
  const daemon::StatusIdentity identity{config.transport, config.can.interface, config.chassis.type,
                                        config.can.dialect};
  daemon::RpcHandler handler(
      control, telemetry, config.chassis.type, config.transport, counters, events,
      [&] { return daemon::status_to_json(identity, daemon::StatusFields{}, 12.3, std::nullopt); },
      [] { return json::object(); });
  daemon::ClientState client;
  client.id = 1;
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto response = handler.handle_line(client, kStatusLine);
    bytes = response->size();
    benchmark::DoNotOptimize(response);
  }
  if (counters.request_errors != 0) state.SkipWithError("status was answered with an error");
  state.SetItemsProcessed(state.iterations());
  state.counters["bytes_per_response"] = static_cast<double>(bytes);
}
BENCHMARK(BM_StatusRequestThroughRpcHandler);

}  // namespace
