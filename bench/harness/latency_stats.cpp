#include "latency_stats.hpp"

#include <algorithm>
#include <cmath>

namespace bench {

namespace {
double percentile(const std::vector<double>& sorted, double fraction) {
  const auto rank = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(sorted.size())));
  return sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1];
}
}  // namespace

LatencySummary summarize(std::vector<double> samples_us) {
  LatencySummary summary;
  summary.count = samples_us.size();
  if (samples_us.empty()) return summary;
  std::sort(samples_us.begin(), samples_us.end());
  summary.p50_us = percentile(samples_us, 0.50);
  summary.p99_us = percentile(samples_us, 0.99);
  summary.max_us = samples_us.back();
  return summary;
}

nlohmann::json LatencySummary::to_json() const {
  return {{"count", count}, {"p50_us", p50_us}, {"p99_us", p99_us}, {"max_us", max_us}};
}

}  // namespace bench
