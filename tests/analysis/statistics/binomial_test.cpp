#include "analysis/statistics/binomial.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/input_error.h"

namespace fovlab::analysis {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct PValueRow {
  uint64_t k;
  uint64_t n;
  double p0;
  Alternative alternative;
  double scipy;
  double mpmath;
  bool scipy_ok;  // false where SciPy 1.10.1 is off by more than 1e-9 relative (n >= 1e9)
};

struct IntervalRow {
  uint64_t k;
  uint64_t n;
  double scipy_lower;
  double scipy_upper;
  double mpmath_lower;  // kNaN where the generator computed none
  double mpmath_upper;
};

// Reference values from SciPy 1.10.1 and an independent mpmath computation; provenance in the
// file's header and in tests/analysis/statistics/make_reference_values.py, which wrote it.
#include "tests/analysis/statistics/binomial_reference.inc"

// Relative tolerance against the references: 1e-9. Values that underflow (both below 1e-300)
// count as equal: SciPy and Boost then differ only in how far into the subnormals they go.
constexpr double kRelativeTolerance = 1e-9;
constexpr double kUnderflow = 1e-300;
// At n = 1e12 Boost 1.74's incomplete beta (Temme's expansion, in long double) is off by up to
// 3e-8 relative from the exact value (e.g. P(X >= 3e11 | n = 1e12, p0 = 0.3): Boost 0.5000003623,
// exact 0.5000003772, which a three-term Edgeworth expansion confirms to 1e-16).
constexpr double kHugeNRelativeTolerance = 1e-7;
constexpr uint64_t kHugeN = 10'000'000'000;
// SciPy finds the Clopper-Pearson bounds with brentq at xtol = 2e-12 (absolute).
constexpr double kScipyIntervalAbsolute = 4e-12;

::testing::AssertionResult close(double actual, double expected, double absolute = 0.0,
                                 double relative = kRelativeTolerance) {
  if (std::isnan(actual) || std::isnan(expected)) {
    return ::testing::AssertionFailure() << "NaN: actual " << actual << ", expected " << expected;
  }
  if (std::abs(actual) < kUnderflow && std::abs(expected) < kUnderflow) {
    return ::testing::AssertionSuccess();
  }
  const double allowed = relative * std::max(std::abs(actual), std::abs(expected)) + absolute;
  if (std::abs(actual - expected) <= allowed) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << std::setprecision(17) << "actual " << actual << ", expected " << expected
                                       << ", relative difference " << std::abs(actual - expected) / std::abs(expected);
}

std::string describe(uint64_t k, uint64_t n, double p0, Alternative alternative) {
  return "k=" + std::to_string(k) + " n=" + std::to_string(n) + " p0=" + std::to_string(p0) + " " +
         alternative_name(alternative);
}

TEST(BinomialTest, MatchesScipyAndMpmathReferenceValues) {
  int checked = 0;
  int scipy_checked = 0;
  for (const PValueRow& row : kPValueRows) {
    const double p = binomial_test_p_value(row.k, row.n, row.p0, row.alternative);
    SCOPED_TRACE(describe(row.k, row.n, row.p0, row.alternative));
    const double relative = row.n >= kHugeN ? kHugeNRelativeTolerance : kRelativeTolerance;
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, 1.0);
    EXPECT_TRUE(close(p, row.mpmath, 0.0, relative)) << "against mpmath";
    if (row.scipy_ok) {
      EXPECT_TRUE(close(p, row.scipy, 0.0, relative)) << "against SciPy";
      ++scipy_checked;
    }
    ++checked;
  }
  EXPECT_GT(checked, 4000);
  // SciPy is set aside only in a few large-n rows (see the fixture's header).
  EXPECT_GT(scipy_checked, checked - 150);
}

TEST(BinomialTest, HalfOfASymmetricDistributionIsExact) {
  // p0 = 0.5, even n: P(X >= n/2) = 1/2 + pmf(n/2)/2, and pmf(n/2) = C(n, n/2) / 2^n
  // = sqrt(2 / (pi n)) (1 - 1/(4n) + ...) by Stirling. SciPy 1.10.1 gives 0.49998948 at n = 1e12.
  for (uint64_t n : {uint64_t{1'000'000}, uint64_t{1'000'000'000}, uint64_t{1'000'000'000'000}}) {
    const double nd = static_cast<double>(n);
    const double pi = 3.14159265358979323846;
    const double central = std::sqrt(2.0 / (pi * nd)) * (1.0 - 1.0 / (4.0 * nd));
    const double expected = 0.5 + central / 2.0;
    EXPECT_TRUE(close(binomial_test_p_value(n / 2, n, 0.5, Alternative::greater), expected)) << "n=" << n;
    EXPECT_TRUE(close(binomial_test_p_value(n / 2, n, 0.5, Alternative::less), expected)) << "n=" << n;
  }
}

TEST(BinomialTest, ReferenceTableCoversTheEdgeCases) {
  // Guards the fixture itself: the cases the brief names must be in it.
  bool large_n[3] = {false, false, false};
  bool degenerate = false, k_zero = false, k_n = false;
  for (const PValueRow& row : kPValueRows) {
    if (row.n == 1'000'000) large_n[0] = true;
    if (row.n == 1'000'000'000) large_n[1] = true;
    if (row.n == 1'000'000'000'000) large_n[2] = true;
    if (row.p0 == 0.0 || row.p0 == 1.0) degenerate = true;
    if (row.k == 0) k_zero = true;
    if (row.k == row.n) k_n = true;
  }
  EXPECT_TRUE(large_n[0] && large_n[1] && large_n[2]);
  EXPECT_TRUE(degenerate && k_zero && k_n);
}

TEST(BinomialTest, ClopperPearsonMatchesReferenceValues) {
  for (const IntervalRow& row : kIntervalRows) {
    const ProportionInterval interval = clopper_pearson_interval(row.k, row.n, 0.95);
    SCOPED_TRACE("k=" + std::to_string(row.k) + " n=" + std::to_string(row.n));
    EXPECT_TRUE(close(interval.lower, row.scipy_lower, kScipyIntervalAbsolute)) << "lower vs SciPy";
    EXPECT_TRUE(close(interval.upper, row.scipy_upper, kScipyIntervalAbsolute)) << "upper vs SciPy";
    if (!std::isnan(row.mpmath_lower)) {
      EXPECT_TRUE(close(interval.lower, row.mpmath_lower)) << "lower vs mpmath";
      EXPECT_TRUE(close(interval.upper, row.mpmath_upper)) << "upper vs mpmath";
    }
    if (row.k == 0) {
      EXPECT_EQ(interval.lower, 0.0);
    }
    if (row.k == row.n) {
      EXPECT_EQ(interval.upper, 1.0);
    }
    EXPECT_LE(interval.lower, static_cast<double>(row.k) / static_cast<double>(row.n));
    EXPECT_GE(interval.upper, static_cast<double>(row.k) / static_cast<double>(row.n));
  }
}

TEST(BinomialTest, ClopperPearsonTextbookValue) {
  // 7 of 20 at 95 %: (0.1539092, 0.5921885), Clopper & Pearson's construction as tabulated by
  // R's binom.test(7, 20) (conf.int 0.1539092 0.5921885).
  const ProportionInterval interval = clopper_pearson_interval(7, 20);
  EXPECT_NEAR(interval.lower, 0.1539092, 5e-8);
  EXPECT_NEAR(interval.upper, 0.5921885, 5e-8);
  // A wider level gives a wider interval.
  const ProportionInterval wide = clopper_pearson_interval(7, 20, 0.99);
  EXPECT_LT(wide.lower, interval.lower);
  EXPECT_GT(wide.upper, interval.upper);
}

// Ye et al. 2022, Table 2 (RMFR study): 12 participants x 6 scenes = 72 trials per comparison, vote
// ratios 68.1 %, 65.3 %, 69.4 %, 48.6 % = 49, 47, 50, 35 of 72, reported as **, **, *** and "no
// significant difference". The one-sided test (greater, p0 = 0.5) gives exactly those stars.
TEST(BinomialTest, YeEtAl2022Table2StarsComeFromTheOneSidedTest) {
  struct Comparison {
    uint64_t k;
    const char* stars;
  };
  const Comparison table[] = {{49, "**"}, {47, "**"}, {50, "***"}, {35, ""}};
  for (const Comparison& c : table) {
    SCOPED_TRACE(std::to_string(c.k) + "/72");
    const double p = binomial_test_p_value(c.k, 72, 0.5, Alternative::greater);
    EXPECT_EQ(significance_stars(p), c.stars) << "p = " << p;
  }
  // The two-sided test does not reproduce the table: 47/72 is p = 0.0128 ("*", not "**").
  const double two_sided = binomial_test_p_value(47, 72, 0.5, Alternative::two_sided);
  EXPECT_NEAR(two_sided, 0.0128, 5e-5);
  EXPECT_EQ(significance_stars(two_sided), "*");
  // With p0 = 0.5 the distribution is symmetric: two-sided is twice the one-sided tail.
  EXPECT_TRUE(close(two_sided, 2.0 * binomial_test_p_value(47, 72, 0.5, Alternative::greater)));
}

TEST(BinomialTest, HandComputedSmallCases) {
  // n = 1: P(X = 1) = p0.
  EXPECT_DOUBLE_EQ(binomial_test_p_value(1, 1, 0.3, Alternative::greater), 0.3);
  EXPECT_DOUBLE_EQ(binomial_test_p_value(0, 1, 0.3, Alternative::less), 0.7);
  EXPECT_DOUBLE_EQ(binomial_test_p_value(1, 1, 0.3, Alternative::less), 1.0);
  EXPECT_DOUBLE_EQ(binomial_test_p_value(0, 1, 0.3, Alternative::greater), 1.0);
  // Two-sided n = 1, p0 = 0.3, k = 1: P(X = 1) = 0.3 <= P(X = 0) = 0.7, so only k itself: 0.3.
  EXPECT_DOUBLE_EQ(binomial_test_p_value(1, 1, 0.3, Alternative::two_sided), 0.3);
  // k = 0: the other outcome is more likely, p = 0.7 + 0 (0.3 > 0.7 is false: nothing added).
  EXPECT_DOUBLE_EQ(binomial_test_p_value(0, 1, 0.3, Alternative::two_sided), 1.0);
  // n = 10, p0 = 0.5, k = 2: P(X <= 2) + P(X >= 8) = 2 * 56 / 1024.
  EXPECT_DOUBLE_EQ(binomial_test_p_value(2, 10, 0.5, Alternative::two_sided), 112.0 / 1024.0);
  EXPECT_DOUBLE_EQ(binomial_test_p_value(8, 10, 0.5, Alternative::two_sided), 112.0 / 1024.0);
  // k == n p0 exactly.
  EXPECT_EQ(binomial_test_p_value(5, 10, 0.5, Alternative::two_sided), 1.0);
  // k = n and k = 0 one-sided: p0^n and (1 - p0)^n.
  EXPECT_DOUBLE_EQ(binomial_test_p_value(10, 10, 0.5, Alternative::greater), 1.0 / 1024.0);
  EXPECT_DOUBLE_EQ(binomial_test_p_value(0, 10, 0.5, Alternative::less), 1.0 / 1024.0);
}

TEST(BinomialTest, SymmetricOutcomesAreTiedByTheTolerance) {
  // With p0 = 0.5, k and n - k are equally likely; the tolerance must count the mirror outcome
  // whatever the rounding of the two pmf values, so both sides give the same p-value.
  for (uint64_t n : {9u, 10u, 71u, 72u, 999u, 1000u}) {
    for (uint64_t k = 0; k <= n; k += (n > 100 ? 37 : 1)) {
      const double a = binomial_test_p_value(k, n, 0.5, Alternative::two_sided);
      const double b = binomial_test_p_value(n - k, n, 0.5, Alternative::two_sided);
      EXPECT_TRUE(close(a, b)) << "k=" << k << " n=" << n;
      if (2 * k != n) {
        const double tail = binomial_test_p_value(std::min(k, n - k), n, 0.5, Alternative::less);
        EXPECT_TRUE(close(a, std::min(1.0, 2.0 * tail))) << "k=" << k << " n=" << n;
      }
    }
  }
}

TEST(BinomialTest, DegenerateNullProportions) {
  for (Alternative alternative : {Alternative::two_sided, Alternative::greater, Alternative::less}) {
    SCOPED_TRACE(alternative_name(alternative));
    // p0 = 0: X = 0 for sure.
    EXPECT_EQ(binomial_test_p_value(0, 7, 0.0, alternative), 1.0);
    EXPECT_EQ(binomial_test_p_value(3, 7, 0.0, alternative), alternative == Alternative::less ? 1.0 : 0.0);
    // p0 = 1: X = n for sure.
    EXPECT_EQ(binomial_test_p_value(7, 7, 1.0, alternative), 1.0);
    EXPECT_EQ(binomial_test_p_value(3, 7, 1.0, alternative), alternative == Alternative::greater ? 1.0 : 0.0);
    EXPECT_EQ(binomial_test_p_value(0, 1'000'000'000'000, 0.0, alternative), 1.0);
  }
}

TEST(BinomialTest, HugeTrialCountsNeedNoLoopOverN) {
  // A loop over n would take minutes at 1e12 (and time out under CTest); the binary search takes
  // a few dozen pmf evaluations. Results are checked against the fixture above; here the extreme
  // and central outcomes must simply come back finite and in range.
  for (uint64_t n : {uint64_t{1'000'000'000}, uint64_t{1'000'000'000'000}, (uint64_t{1} << 53) - 1}) {
    for (double p0 : {0.5, 0.3, 1e-9, 1.0 - 1e-9}) {
      const auto center = static_cast<uint64_t>(static_cast<double>(n) * p0);
      for (uint64_t k : {uint64_t{0}, uint64_t{1}, center - 1, center, center + 1, n - 1, n}) {
        for (Alternative alternative : {Alternative::two_sided, Alternative::greater, Alternative::less}) {
          const double p = binomial_test_p_value(k, n, p0, alternative);
          EXPECT_TRUE(p >= 0.0 && p <= 1.0) << describe(k, n, p0, alternative) << " p=" << p;
        }
      }
    }
  }
  const ProportionInterval interval = clopper_pearson_interval(500'000'000'000, 1'000'000'000'000);
  EXPECT_LT(interval.lower, 0.5);
  EXPECT_GT(interval.upper, 0.5);
  EXPECT_NEAR(interval.upper - interval.lower, 2 * 1.959964 * 5e-7, 1e-11);
}

TEST(BinomialTest, InvalidArgumentsThrow) {
  EXPECT_THROW(binomial_test_p_value(0, 0, 0.5, Alternative::two_sided), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(11, 10, 0.5, Alternative::greater), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, -0.1, Alternative::less), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, 1.5, Alternative::less), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, kNaN, Alternative::two_sided), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, uint64_t{1} << 53, 0.5, Alternative::two_sided), std::invalid_argument);
  EXPECT_THROW(binomial_test_p_value(1, 10, 0.5, static_cast<Alternative>(17)), std::invalid_argument);
  EXPECT_THROW(clopper_pearson_interval(0, 0), std::invalid_argument);
  EXPECT_THROW(clopper_pearson_interval(5, 4), std::invalid_argument);
  EXPECT_THROW(clopper_pearson_interval(1, 4, 0.0), std::invalid_argument);
  EXPECT_THROW(clopper_pearson_interval(1, 4, 1.0), std::invalid_argument);
  EXPECT_THROW(clopper_pearson_interval(1, 4, kNaN), std::invalid_argument);
  EXPECT_THROW(significance_stars(kNaN), std::invalid_argument);
}

TEST(BinomialTest, SignificanceStarsThresholds) {
  EXPECT_EQ(significance_stars(0.0), "***");
  EXPECT_EQ(significance_stars(0.000999), "***");
  EXPECT_EQ(significance_stars(0.001), "**");
  EXPECT_EQ(significance_stars(0.00999), "**");
  EXPECT_EQ(significance_stars(0.01), "*");
  EXPECT_EQ(significance_stars(0.0499), "*");
  EXPECT_EQ(significance_stars(0.05), "");
  EXPECT_EQ(significance_stars(1.0), "");
}

TEST(BinomialTest, AlternativeNamesRoundTrip) {
  for (Alternative alternative : {Alternative::two_sided, Alternative::greater, Alternative::less}) {
    EXPECT_EQ(parse_alternative(alternative_name(alternative)), alternative);
  }
  EXPECT_STREQ(alternative_name(Alternative::two_sided), "two-sided");
  EXPECT_STREQ(alternative_name(Alternative::greater), "greater");
  EXPECT_STREQ(alternative_name(Alternative::less), "less");
  for (const char* bad : {"", "two_sided", "Greater", "both", "less "}) {
    try {
      parse_alternative(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& error) {
      EXPECT_EQ(std::string(error.what()).rfind("--alternative: ", 0), 0u) << error.what();
    }
  }
}

// p-values below 1e-300 (issue 40): log10 p in log space, against mpmath at 60 digits
// (tests/analysis/statistics/make_log10_reference.py printed these rows), and 0, never a
// subnormal, from binomial_test_p_value.
struct Log10Row {
  uint64_t k, n;
  double p0;
  Alternative alternative;
  double log10_p;
};

TEST(BinomialLog10, MatchesMpmathWhereThePValueUnderflows) {
  const Log10Row rows[] = {
      {0, 1000000, 0.5, Alternative::less, -301029.9956639812},
      {100, 1000000, 0.5, Alternative::less, -300587.96777402902},
      {999900, 1000000, 0.5, Alternative::greater, -300587.96777402902},
      {0, 2000, 0.5, Alternative::two_sided, -601.75896133229841},
      {10, 100000, 0.3, Alternative::two_sided, -15450.167033963769},
      {99000, 100000, 0.3, Alternative::two_sided, -49489.677067506433},
      {5, 20000, 0.5, Alternative::two_sided, -6000.8730231117316},
  };
  for (const Log10Row& row : rows) {
    SCOPED_TRACE(describe(row.k, row.n, row.p0, row.alternative));
    EXPECT_TRUE(close(binomial_test_log10_p_value(row.k, row.n, row.p0, row.alternative), row.log10_p, 0.0, 1e-10));
    EXPECT_EQ(binomial_test_p_value(row.k, row.n, row.p0, row.alternative), 0.0);
  }
}

TEST(BinomialLog10, KZeroAtHugeNIsTwoOverTwoToTheN) {
  for (uint64_t n : {uint64_t{1'000'000}, uint64_t{1'000'000'000}, uint64_t{1'000'000'000'000}}) {
    const double expected = std::log10(2.0) - double(n) * std::log10(2.0);
    EXPECT_TRUE(close(binomial_test_log10_p_value(0, n, 0.5, Alternative::two_sided), expected, 0.0, 1e-12))
        << "n=" << n;
    EXPECT_EQ(binomial_test_p_value(0, n, 0.5, Alternative::two_sided), 0.0) << "n=" << n;
    EXPECT_EQ(p_value_text(0.0, expected, 4).rfind("< 1e-300 (log10 p = -", 0), 0u);
  }
}

TEST(BinomialLog10, EqualsLog10OfThePValueWhereItDoesNotUnderflow) {
  EXPECT_DOUBLE_EQ(binomial_test_log10_p_value(47, 72, 0.5, Alternative::greater),
                   std::log10(binomial_test_p_value(47, 72, 0.5, Alternative::greater)));
  EXPECT_EQ(p_value_text(0.006387, std::log10(0.006387), 4), "0.006387");
}

}  // namespace
}  // namespace fovlab::analysis
