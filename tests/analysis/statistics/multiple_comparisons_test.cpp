#include "analysis/statistics/multiple_comparisons.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <vector>

namespace fovlab::analysis {
namespace {

void expect_adjusted(const std::vector<double>& p, const std::vector<double>& expected) {
  const std::vector<double> adjusted = holm_adjusted(p);
  ASSERT_EQ(adjusted.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_NEAR(adjusted[i], expected[i], 1e-15) << "index " << i;
  }
}

TEST(HolmAdjusted, EmptyInputGivesEmptyOutput) { EXPECT_TRUE(holm_adjusted({}).empty()); }

TEST(HolmAdjusted, SingleValueIsUnchanged) {
  expect_adjusted({0.03}, {0.03});
  expect_adjusted({1.0}, {1.0});
  expect_adjusted({0.0}, {0.0});
}

TEST(HolmAdjusted, AlreadySorted) {
  // m = 5: 5(0.01) = 0.05, 4(0.02) = 0.08, 3(0.03) = 0.09, 2(0.04) = 0.08 -> 0.09 (running max),
  // 1(0.05) = 0.05 -> 0.09. R: p.adjust(c(.01, .02, .03, .04, .05), "holm").
  expect_adjusted({0.01, 0.02, 0.03, 0.04, 0.05}, {0.05, 0.08, 0.09, 0.09, 0.09});
}

TEST(HolmAdjusted, ReversedInputKeepsInputOrder) {
  expect_adjusted({0.05, 0.04, 0.03, 0.02, 0.01}, {0.09, 0.09, 0.09, 0.08, 0.05});
}

TEST(HolmAdjusted, UnsortedWorkedExample) {
  // Holm's procedure on 0.01, 0.04, 0.03, 0.005 (m = 4): sorted 0.005, 0.01, 0.03, 0.04 give
  // 4(0.005) = 0.02, 3(0.01) = 0.03, 2(0.03) = 0.06, 1(0.04) = 0.04 -> 0.06.
  expect_adjusted({0.01, 0.04, 0.03, 0.005}, {0.03, 0.06, 0.06, 0.02});
}

TEST(HolmAdjusted, TiesGetEqualAdjustedValues) {
  // Ties: 3(0.02) = 0.06, 2(0.02) = 0.04 -> 0.06, 1(0.5) = 0.5. Either order of the tied
  // values gives the same result.
  expect_adjusted({0.02, 0.5, 0.02}, {0.06, 0.5, 0.06});
  expect_adjusted({0.5, 0.02, 0.02}, {0.5, 0.06, 0.06});
  expect_adjusted({0.2, 0.2, 0.2, 0.2}, {0.8, 0.8, 0.8, 0.8});
}

TEST(HolmAdjusted, CapsAtOne) {
  // 3(0.4) = 1.2 -> 1; 2(0.6) = 1.2 -> 1; 1(0.7) = 0.7 but the running max keeps 1.
  expect_adjusted({0.7, 0.4, 0.6}, {1.0, 1.0, 1.0});
  // 4(0.001) = 0.004, 3(0.3) = 0.9, 2(0.6) = 1.2 -> 1, 1(0.9) -> 1.
  expect_adjusted({0.9, 0.001, 0.6, 0.3}, {1.0, 0.004, 1.0, 0.9});
  expect_adjusted({1.0, 1.0}, {1.0, 1.0});
}

TEST(HolmAdjusted, SeedTableTwoOneSidedPValues) {
  // Ye et al. 2022, Table 2: one-sided p-values of 49, 47, 50, 35 of 72 (rounded to 4 digits):
  // 0.001471, 0.006387, 0.0006468, 0.6380. Holm: 4(0.0006468), 3(0.001471), 2(0.006387), 0.6380.
  // After the correction 47/72 is 0.0128 ("*", not the paper's "**").
  expect_adjusted({0.001471, 0.006387, 0.0006468, 0.6380}, {3 * 0.001471, 2 * 0.006387, 4 * 0.0006468, 0.6380});
}

TEST(HolmAdjusted, MonotoneInTheRankOfTheInput) {
  const std::vector<double> p = {0.04, 0.001, 0.3, 0.012, 0.012, 0.8, 0.0049, 0.049};
  const std::vector<double> adjusted = holm_adjusted(p);
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_GE(adjusted[i], p[i]);
    EXPECT_LE(adjusted[i], 1.0);
    for (std::size_t j = 0; j < p.size(); ++j) {
      if (p[i] <= p[j]) {
        EXPECT_LE(adjusted[i], adjusted[j]) << i << " vs " << j;
      }
    }
  }
}

TEST(HolmAdjusted, RejectsNaNAndValuesOutsideTheUnitInterval) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(holm_adjusted({0.1, nan}), std::invalid_argument);
  EXPECT_THROW(holm_adjusted({-0.01}), std::invalid_argument);
  EXPECT_THROW(holm_adjusted({0.2, 1.5}), std::invalid_argument);
}

}  // namespace
}  // namespace fovlab::analysis
