#include "analysis/statistics/percentile.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fovlab::analysis {

std::optional<double> nearest_rank_percentile(std::vector<double> values, double percent) {
  if (!(percent >= 0.0 && percent <= 100.0))
    throw std::invalid_argument("nearest_rank_percentile: percent outside [0, 100]");
  if (values.empty()) return std::nullopt;
  for (const double value : values)
    if (!std::isfinite(value)) throw std::invalid_argument("nearest_rank_percentile: a value is not finite");
  const size_t n = values.size();
  // Rank ceil(p/100 * n), at least 1. p * n / 100 rather than p / 100 * n keeps whole ranks whole
  // (95 * 20 / 100 is exactly 19).
  size_t rank = static_cast<size_t>(std::ceil(percent * static_cast<double>(n) / 100.0));
  rank = std::clamp<size_t>(rank, 1, n);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(rank - 1), values.end());
  return values[rank - 1];
}

LatencySummary summarise_latency(const std::vector<double>& gaze_age_s) {
  LatencySummary summary;
  summary.refreshes = gaze_age_s.size();
  if (const auto median = nearest_rank_percentile(gaze_age_s, 50.0)) summary.median_ms = *median * 1e3;
  if (const auto p95 = nearest_rank_percentile(gaze_age_s, 95.0)) summary.p95_ms = *p95 * 1e3;
  return summary;
}

}  // namespace fovlab::analysis
