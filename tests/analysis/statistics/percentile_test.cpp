#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/statistics/percentile.h"

namespace fovlab::analysis {
namespace {

TEST(StatisticsPercentile, NearestRank) {
  EXPECT_EQ(nearest_rank_percentile({}, 50.0), std::nullopt);
  EXPECT_EQ(nearest_rank_percentile({7.0}, 95.0), 7.0);
  // 1..20: the median is rank 10 (the lower middle value), p95 rank 19, p100 the largest, p0 the smallest.
  std::vector<double> values;
  for (int i = 20; i >= 1; --i) values.push_back(i);
  EXPECT_EQ(nearest_rank_percentile(values, 50.0), 10.0);
  EXPECT_EQ(nearest_rank_percentile(values, 95.0), 19.0);
  EXPECT_EQ(nearest_rank_percentile(values, 100.0), 20.0);
  EXPECT_EQ(nearest_rank_percentile(values, 0.0), 1.0);
  EXPECT_EQ(nearest_rank_percentile(values, 96.0), 20.0);  // ceil(19.2) = 20
  EXPECT_EQ(nearest_rank_percentile({3.0, 1.0, 2.0}, 50.0), 2.0);
  EXPECT_THROW(nearest_rank_percentile(values, 101.0), std::invalid_argument);
  EXPECT_THROW(nearest_rank_percentile({std::numeric_limits<double>::quiet_NaN()}, 50.0), std::invalid_argument);
}

TEST(StatisticsPercentile, LatencySummaryInMilliseconds) {
  const LatencySummary none = summarise_latency({});
  EXPECT_EQ(none.refreshes, 0u);
  EXPECT_FALSE(none.median_ms.has_value());
  const LatencySummary summary = summarise_latency({0.050, 0.010, 0.020, 0.030});
  EXPECT_EQ(summary.refreshes, 4u);
  EXPECT_DOUBLE_EQ(*summary.median_ms, 20.0);
  EXPECT_DOUBLE_EQ(*summary.p95_ms, 50.0);
}

}  // namespace
}  // namespace fovlab::analysis
