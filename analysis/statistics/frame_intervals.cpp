#include "analysis/statistics/frame_intervals.h"

#include <algorithm>
#include <cmath>

namespace fovlab::analysis {
namespace {

bool known_rate(const std::optional<double>& refresh_hz) {
  return refresh_hz && std::isfinite(*refresh_hz) && *refresh_hz > 0.0;
}

// The value (µs) of rank ceil(p / 100 * n) in ascending order, at least rank 1.
int64_t nearest_rank_us(const std::map<int64_t, uint64_t>& counts, uint64_t n, double percent) {
  uint64_t rank = static_cast<uint64_t>(std::ceil(percent * static_cast<double>(n) / 100.0));
  rank = std::clamp<uint64_t>(rank, 1, n);
  uint64_t seen = 0;
  for (const auto& [us, count] : counts) {
    seen += count;
    if (seen >= rank) return us;
  }
  return counts.rbegin()->first;
}

// Median, SD, p99 and max from the counts (late and refresh_hz are the caller's).
void fill_statistics(FrameIntervalSummary& summary) {
  uint64_t n = 0;
  long double sum_us = 0.0L;
  for (const auto& [us, count] : summary.count_by_us) {
    n += count;
    sum_us += static_cast<long double>(us) * static_cast<long double>(count);
  }
  summary.intervals = n;
  summary.median_ms = summary.sd_ms = summary.p99_ms = summary.max_ms = summary.late_share = std::nullopt;
  if (n == 0) return;
  const long double mean_us = sum_us / static_cast<long double>(n);
  long double squares = 0.0L;
  for (const auto& [us, count] : summary.count_by_us) {
    const long double d = static_cast<long double>(us) - mean_us;
    squares += d * d * static_cast<long double>(count);
  }
  if (n > 1) summary.sd_ms = static_cast<double>(std::sqrt(squares / static_cast<long double>(n - 1))) / 1e3;
  summary.median_ms = static_cast<double>(nearest_rank_us(summary.count_by_us, n, 50.0)) / 1e3;
  summary.p99_ms = static_cast<double>(nearest_rank_us(summary.count_by_us, n, 99.0)) / 1e3;
  summary.max_ms = static_cast<double>(summary.count_by_us.rbegin()->first) / 1e3;
  summary.late_share = static_cast<double>(summary.late) / static_cast<double>(n);
}

}  // namespace

FrameIntervalSummary summarise_frame_intervals(const std::vector<double>& interval_s,
                                               std::optional<double> refresh_hz) {
  FrameIntervalSummary summary;
  if (known_rate(refresh_hz)) summary.refresh_hz = refresh_hz;
  const double late_beyond_us = summary.refresh_hz ? kLateRefreshPeriods * 1e6 / *summary.refresh_hz : 0.0;
  for (const double seconds : interval_s) {
    if (!std::isfinite(seconds) || seconds < 0.0 || seconds > 1e9) continue;
    const int64_t us = std::llround(seconds * 1e6);
    ++summary.count_by_us[us];
    if (summary.refresh_hz && static_cast<double>(us) > late_beyond_us) ++summary.late;
  }
  fill_statistics(summary);
  return summary;
}

FrameIntervalSummary pool_frame_intervals(const std::vector<const FrameIntervalSummary*>& summaries) {
  FrameIntervalSummary pooled;
  bool first = true;
  bool same_rate = true;
  for (const FrameIntervalSummary* summary : summaries) {
    if (!summary || summary->count_by_us.empty()) continue;
    for (const auto& [us, count] : summary->count_by_us) pooled.count_by_us[us] += count;
    pooled.late += summary->late;
    if (first) pooled.refresh_hz = summary->refresh_hz;
    else if (pooled.refresh_hz != summary->refresh_hz) same_rate = false;
    first = false;
  }
  if (!same_rate) pooled.refresh_hz.reset();
  fill_statistics(pooled);
  return pooled;
}

}  // namespace fovlab::analysis
