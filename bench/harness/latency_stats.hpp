#pragma once

#include <cstddef>
#include <vector>

#include <nlohmann/json.hpp>

namespace bench {

struct LatencySummary {
  std::size_t count = 0;
  double p50_us = 0.0;
  double p99_us = 0.0;
  double max_us = 0.0;
  nlohmann::json to_json() const;
};

LatencySummary summarize(std::vector<double> samples_us);

}  // namespace bench
