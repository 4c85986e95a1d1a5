#include "stats_report.hpp"

#include <cmath>

namespace wheeltec::daemon {

nlohmann::json stats_to_json(const ChassisLink& link, std::uint64_t records_accepted, const ApiCounters& api,
                             double uptime_s) {
  nlohmann::json stats = nlohmann::json::object();
  link.add_stats(stats);
  stats["records_accepted"] = records_accepted;
  stats["notifications_dropped"] = api.notifications_dropped;
  stats["clients"] = api.clients;
  stats["clients_total"] = api.clients_total;
  stats["clients_refused"] = api.clients_refused;
  stats["clients_disconnected_slow"] = api.clients_disconnected_slow;
  stats["requests"] = api.requests;
  stats["request_errors"] = api.request_errors;
  stats["api"] = {{"events_dropped", api.events_dropped}};
  stats["uptime_s"] = std::round(uptime_s * 1000.0) / 1000.0;
  return stats;
}

}  // namespace wheeltec::daemon
