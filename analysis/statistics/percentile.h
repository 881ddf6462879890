#pragma once
// Percentiles by nearest rank, the one definition fovlab uses (docs/analysis.md): the p-th
// percentile of n values is the smallest value such that at least p % of the values are at or
// below it, i.e. the value of rank ceil(p / 100 * n) in ascending order (rank 1 for p = 0). It is
// always one of the values (no interpolation); the median (p = 50) of an even count is the lower
// of the two middle values.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace fovlab::analysis {

// nullopt for no values; std::invalid_argument for p outside [0, 100] or a non-finite value.
std::optional<double> nearest_rank_percentile(std::vector<double> values, double percent);

// Gaze-to-present latency of a session (or a participant): from every refresh's gaze sample age
// at present time, in seconds.
struct LatencySummary {
  size_t refreshes = 0;             // ages counted (refreshes with a gaze sample)
  std::optional<double> median_ms;  // nearest rank; none without refreshes
  std::optional<double> p95_ms;
};

LatencySummary summarise_latency(const std::vector<double>& gaze_age_s);

}  // namespace fovlab::analysis
