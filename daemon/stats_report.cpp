#include "stats_report.hpp"

#include <cmath>

namespace wheeltec::daemon {

nlohmann::json stats_to_json(const CanLinkCounters& link, const ReassemblyCounters& reassembly,
                             const ApiCounters& api, double uptime_s) {
  nlohmann::json discarded = nlohmann::json::object();
  for (std::size_t i = 0; i < kDiscardReasonCount; ++i) {
    discarded[std::string(to_string(static_cast<DiscardReason>(i)))] = reassembly.discarded[i];
  }
  nlohmann::json rejected = nlohmann::json::object();
  for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
    rejected[std::string(to_string(static_cast<RejectReason>(i)))] = reassembly.rejected[i];
  }
  return nlohmann::json{
      {"frames_received", link.frames_received},
      {"frames_sent", link.frames_sent},
      {"send_errors", link.send_errors},
      {"error_frames", link.error_frames},
      {"records_accepted", reassembly.accepted},
      {"groups_discarded", std::move(discarded)},
      {"records_rejected", std::move(rejected)},
      {"resync_skipped", reassembly.resync_skipped},
      {"notifications_dropped", api.notifications_dropped},
      {"clients", api.clients},
      {"clients_total", api.clients_total},
      {"clients_refused", api.clients_refused},
      {"clients_disconnected_slow", api.clients_disconnected_slow},
      {"requests", api.requests},
      {"request_errors", api.request_errors},
      {"uptime_s", std::round(uptime_s * 1000.0) / 1000.0},
  };
}

}  // namespace wheeltec::daemon
