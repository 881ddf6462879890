#pragma once
// The intervals between presented frames of a session (or a study): how evenly the display showed
// the stimuli (docs/analysis.md, "Frame intervals"). An interval is the time between two
// consecutive refreshes of one stimulus presentation (a stimulus event's `present_s`); the gap
// between two presentations (a response, a blank) is not one. Intervals are kept rounded to the
// microsecond, as counts per value, so summaries merge exactly (a study pools its sessions) and
// every figure is computed on those rounded values.
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <vector>

namespace fovlab::analysis {

// A refresh interval is late when it exceeds this many refresh periods (one refresh missed, or
// more).
inline constexpr double kLateRefreshPeriods = 1.5;

struct FrameIntervalSummary {
  // The display's refresh rate the late intervals are measured against (the log header's
  // display.measured_refresh_hz); none: unknown (no interval is then counted late), or sessions at
  // different rates pooled (each counted late against its own rate).
  std::optional<double> refresh_hz;
  uint64_t intervals = 0;
  std::optional<double> median_ms;  // nearest rank (analysis/statistics/percentile.h)
  std::optional<double> sd_ms;      // sample SD (n - 1); none with fewer than two
  std::optional<double> p99_ms;     // nearest rank
  std::optional<double> max_ms;
  uint64_t late = 0;                        // intervals > kLateRefreshPeriods refresh periods
  std::optional<double> late_share;         // late / intervals; none without intervals
  std::map<int64_t, uint64_t> count_by_us;  // every interval, rounded to the microsecond: its count
};

// The summary of `interval_s` (seconds; negative or non-finite values are left out) at
// `refresh_hz` (<= 0 or non-finite: unknown).
FrameIntervalSummary summarise_frame_intervals(const std::vector<double>& interval_s, std::optional<double> refresh_hz);

// Several summaries pooled (a study's sessions): counts added, late counted per session against its
// own refresh rate; refresh_hz kept when every non-empty summary has the same one.
FrameIntervalSummary pool_frame_intervals(const std::vector<const FrameIntervalSummary*>& summaries);

}  // namespace fovlab::analysis
