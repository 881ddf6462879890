#include "analysis/statistics/binomial.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <cstdint>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/binomial.hpp>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::analysis {
namespace {

using Distribution = boost::math::binomial_distribution<double>;

// Boost takes the trial count as a double. Up to 2^53 - 1 every count, and n + 1, is an exact
// double, so no outcome is rounded onto its neighbour.
constexpr uint64_t kMaxTrials = (uint64_t{1} << 53) - 1;

// R's binom.test and SciPy's binomtest treat outcomes whose probability is within this relative
// margin of P(X = k) as equally likely (it absorbs rounding in the pmf of symmetric outcomes).
constexpr double kRelativeTolerance = 1.0 + 1e-7;

void check_counts(uint64_t k, uint64_t n, const char* function) {
  if (n == 0) throw std::invalid_argument(std::string(function) + ": n must be at least 1");
  if (n > kMaxTrials) {
    throw std::invalid_argument(std::string(function) + ": n = " + std::to_string(n) + " exceeds 2^53 - 1");
  }
  if (k > n) {
    throw std::invalid_argument(std::string(function) + ": k = " + std::to_string(k) +
                                " exceeds n = " + std::to_string(n));
  }
}

// The first i in [begin, end) with predicate(i) true, for a predicate that is false and then true
// on the range; end if it is never true. O(log(end - begin)) calls.
template <typename Predicate>
uint64_t partition_point(uint64_t begin, uint64_t end, Predicate predicate) {
  while (begin < end) {
    const uint64_t middle = begin + (end - begin) / 2;
    if (predicate(middle)) {
      end = middle;
    } else {
      begin = middle + 1;
    }
  }
  return begin;
}

// The binomial distribution with 0 < p < 1 and the tail sums the tests need, on uint64 outcomes.
class Binomial {
 public:
  Binomial(uint64_t n, double p) : n_(n), p_(p), distribution_(static_cast<double>(n), p) {}

  double pmf(uint64_t i) const { return boost::math::pdf(distribution_, static_cast<double>(i)); }
  // P(X <= i).
  double at_most(uint64_t i) const {
    if (i >= n_) return 1.0;
    return boost::math::cdf(distribution_, static_cast<double>(i));
  }
  // P(X >= i).
  double at_least(uint64_t i) const {
    if (i == 0) return 1.0;
    if (i > n_) return 0.0;
    return boost::math::cdf(boost::math::complement(distribution_, static_cast<double>(i - 1)));
  }

  // The largest mode, floor((n + 1) p), computed exactly: pmf(i + 1) >= pmf(i) exactly when
  // i + 1 <= (n + 1) p, so the pmf is non-decreasing on [0, mode] and non-increasing on [mode, n].
  uint64_t mode() const {
    const double a = static_cast<double>(n_ + 1);  // exact, n + 1 <= 2^53
    const double product = a * p_;
    const double error = std::fma(a, p_, -product);  // a * p == product + error, exactly
    double floor_value = std::floor(product);
    // product is a double, and so is every integer below 2^53: the rounding can move the exact
    // value across an integer only when product itself is that integer.
    if (floor_value == product && error < 0) floor_value -= 1.0;
    if (floor_value <= 0) return 0;
    const auto mode = static_cast<uint64_t>(floor_value);
    return std::min(mode, n_);
  }

  // How many i in [begin, end) have pmf(i) <= threshold, by binary search on the two monotone
  // pieces of the range either side of the mode: O(log n) pmf evaluations.
  uint64_t count_at_most(uint64_t begin, uint64_t end, double threshold) const {
    if (begin >= end) return 0;
    const uint64_t split = mode() + 1;  // [0, split) rising, [split, n] falling
    uint64_t count = 0;
    // Rising piece: the outcomes with pmf <= threshold come first.
    const uint64_t rising_end = std::min(end, split);
    if (begin < rising_end) {
      const uint64_t first_above = partition_point(begin, rising_end, [&](uint64_t i) { return pmf(i) > threshold; });
      count += first_above - begin;
    }
    // Falling piece: the outcomes with pmf <= threshold come last.
    const uint64_t falling_begin = std::max(begin, split);
    if (falling_begin < end) {
      const uint64_t first_at_most =
          partition_point(falling_begin, end, [&](uint64_t i) { return pmf(i) <= threshold; });
      count += end - first_at_most;
    }
    return count;
  }

 private:
  uint64_t n_;
  double p_;
  Distribution distribution_;
};

double two_sided_p_value(uint64_t k, uint64_t n, double p0) {
  const Binomial binomial(n, p0);
  const double threshold = binomial.pmf(k) * kRelativeTolerance;
  // n p0 in double precision, as R and SciPy compute it: it decides which side k lies on.
  const double expected = static_cast<double>(n) * p0;
  const double kd = static_cast<double>(k);
  if (kd == expected) return 1.0;
  if (kd < expected) {
    // The other side is [ceil(n p0), n]; the y outcomes there no more likely than k are its top y.
    const auto begin = static_cast<uint64_t>(std::ceil(expected));
    const uint64_t y = binomial.count_at_most(begin, n + 1, threshold);
    return binomial.at_most(k) + binomial.at_least(n - y + 1);
  }
  // The other side is [0, floor(n p0)]; the y outcomes there no more likely than k are its bottom y.
  const auto end = static_cast<uint64_t>(std::floor(expected)) + 1;
  const uint64_t y = binomial.count_at_most(0, end, threshold);
  const double lower_tail = y == 0 ? 0.0 : binomial.at_most(y - 1);
  return lower_tail + binomial.at_least(k);
}

// p0 = 0 or 1: X is certain to equal `outcome` (0 or n).
double degenerate_p_value(uint64_t k, uint64_t outcome, Alternative alternative) {
  switch (alternative) {
    case Alternative::greater:
      return outcome >= k ? 1.0 : 0.0;
    case Alternative::less:
      return outcome <= k ? 1.0 : 0.0;
    case Alternative::two_sided:
      return outcome == k ? 1.0 : 0.0;
  }
  throw std::invalid_argument("binomial_test_p_value: unknown alternative");
}

// Log space, for p-values a double cannot hold (binomial_test_log10_p_value).
class LogBinomial {
 public:
  LogBinomial(uint64_t n, double p)
      : n_(n), p_(p), log_p_(std::log(p)), log_q_(std::log1p(-p)), log_n_factorial_(std::lgamma(double(n) + 1.0)) {}

  double log_pmf(uint64_t i) const {
    const double log_choose =
        i == 0 || i == n_ ? 0.0 : log_n_factorial_ - std::lgamma(double(i) + 1.0) - std::lgamma(double(n_ - i) + 1.0);
    return log_choose + (i == 0 ? 0.0 : double(i) * log_p_) + (i == n_ ? 0.0 : double(n_ - i) * log_q_);
  }
  // log P(X <= k) for k in the lower tail: from k down, the terms fall (the pmf is log-concave).
  double log_at_most(uint64_t k) const {
    double sum = 1.0, term = 1.0;
    for (uint64_t i = k; i > 0; --i) {
      term *= double(i) * (1.0 - p_) / (double(n_ - i + 1) * p_);  // pmf(i - 1) / pmf(i)
      sum += term;
      if (term < 1e-17 * sum) break;
    }
    return log_pmf(k) + std::log(sum);
  }
  // log P(X >= k) for k in the upper tail.
  double log_at_least(uint64_t k) const {
    double sum = 1.0, term = 1.0;
    for (uint64_t i = k; i < n_; ++i) {
      term *= double(n_ - i) * p_ / (double(i + 1) * (1.0 - p_));  // pmf(i + 1) / pmf(i)
      sum += term;
      if (term < 1e-17 * sum) break;
    }
    return log_pmf(k) + std::log(sum);
  }

 private:
  uint64_t n_;
  double p_, log_p_, log_q_, log_n_factorial_;
};

double log_sum(double a, double b) {
  if (std::isinf(a) && a < 0) return b;
  if (std::isinf(b) && b < 0) return a;
  const double high = std::max(a, b);
  return high + std::log1p(std::exp(std::min(a, b) - high));
}

// The two-sided p-value's natural log: k's tail and the outcomes on the other side no more likely
// than k (two_sided_p_value's rule), every probability in log space.
double log_two_sided_p_value(uint64_t k, uint64_t n, double p0) {
  const LogBinomial binomial(n, p0);
  const double threshold = binomial.log_pmf(k) + std::log(kRelativeTolerance);
  const double expected = static_cast<double>(n) * p0;
  const uint64_t mode = Binomial(n, p0).mode();
  if (static_cast<double>(k) < expected) {
    // The other side, beyond the mode, falls: its outcomes at or below the threshold are its top ones.
    const auto begin = std::max<uint64_t>(mode, static_cast<uint64_t>(std::ceil(expected)));
    const uint64_t first = partition_point(begin, n + 1, [&](uint64_t i) { return binomial.log_pmf(i) <= threshold; });
    const double other = first > n ? -std::numeric_limits<double>::infinity() : binomial.log_at_least(first);
    return log_sum(binomial.log_at_most(k), other);
  }
  // The other side, below the mode, rises: its outcomes at or below the threshold are its bottom ones.
  const auto end = std::min<uint64_t>(mode, static_cast<uint64_t>(std::floor(expected))) + 1;
  const uint64_t first_above = partition_point(0, end, [&](uint64_t i) { return binomial.log_pmf(i) > threshold; });
  const double other =
      first_above == 0 ? -std::numeric_limits<double>::infinity() : binomial.log_at_most(first_above - 1);
  return log_sum(other, binomial.log_at_least(k));
}

}  // namespace

double binomial_test_log10_p_value(uint64_t k, uint64_t n, double p0, Alternative alternative) {
  const double p_value = binomial_test_p_value(k, n, p0, alternative);
  if (p_value >= kSmallestPrintedPValue || p0 == 0.0 || p0 == 1.0) return std::log10(p_value);
  double log_p = 0.0;
  switch (alternative) {
    case Alternative::greater:
      log_p = LogBinomial(n, p0).log_at_least(k);
      break;
    case Alternative::less:
      log_p = LogBinomial(n, p0).log_at_most(k);
      break;
    case Alternative::two_sided:
      log_p = log_two_sided_p_value(k, n, p0);
      break;
  }
  return std::min(0.0, log_p / std::log(10.0));
}

std::string p_value_text(double p_value, double log10_p, int significant_digits) {
  if (p_value >= kSmallestPrintedPValue || !std::isfinite(log10_p)) return format_number(p_value, significant_digits);
  char text[96];
  std::snprintf(text, sizeof text, "< 1e-300 (log10 p = %.1f)", log10_p);
  return text;
}

const char* alternative_name(Alternative alternative) {
  switch (alternative) {
    case Alternative::two_sided:
      return "two-sided";
    case Alternative::greater:
      return "greater";
    case Alternative::less:
      return "less";
  }
  throw std::invalid_argument("alternative_name: unknown alternative");
}

Alternative parse_alternative(const std::string& text) {
  if (text == "two-sided") return Alternative::two_sided;
  if (text == "greater") return Alternative::greater;
  if (text == "less") return Alternative::less;
  throw InputError("--alternative: expected two-sided, greater or less, got '" + text + "'");
}

double binomial_test_p_value(uint64_t k, uint64_t n, double p0, Alternative alternative) {
  check_counts(k, n, "binomial_test_p_value");
  if (!(p0 >= 0.0 && p0 <= 1.0)) {
    throw std::invalid_argument("binomial_test_p_value: p0 = " + exact_number_text(p0) + " is outside [0, 1]");
  }
  if (alternative != Alternative::two_sided && alternative != Alternative::greater &&
      alternative != Alternative::less) {
    throw std::invalid_argument("binomial_test_p_value: unknown alternative");
  }
  if (p0 == 0.0) return degenerate_p_value(k, 0, alternative);
  if (p0 == 1.0) return degenerate_p_value(k, n, alternative);

  double p_value = 0.0;
  switch (alternative) {
    case Alternative::greater:
      p_value = Binomial(n, p0).at_least(k);
      break;
    case Alternative::less:
      p_value = Binomial(n, p0).at_most(k);
      break;
    case Alternative::two_sided:
      p_value = two_sided_p_value(k, n, p0);
      break;
  }
  return p_value < kSmallestPrintedPValue ? 0.0 : std::clamp(p_value, 0.0, 1.0);
}

ProportionInterval clopper_pearson_interval(uint64_t k, uint64_t n, double confidence) {
  check_counts(k, n, "clopper_pearson_interval");
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw std::invalid_argument("clopper_pearson_interval: confidence = " + exact_number_text(confidence) +
                                " is outside (0, 1)");
  }
  // Each bound leaves (1 - confidence) / 2 in its tail (Clopper & Pearson 1934).
  const double tail = (1.0 - confidence) / 2.0;
  const auto trials = static_cast<double>(n);
  const auto successes = static_cast<double>(k);
  ProportionInterval interval;
  interval.lower = k == 0 ? 0.0
                          : Distribution::find_lower_bound_on_p(trials, successes, tail,
                                                                Distribution::clopper_pearson_exact_interval);
  interval.upper = k == n ? 1.0
                          : Distribution::find_upper_bound_on_p(trials, successes, tail,
                                                                Distribution::clopper_pearson_exact_interval);
  return interval;
}

std::string significance_stars(double p_value) {
  if (std::isnan(p_value)) throw std::invalid_argument("significance_stars: p-value is NaN");
  if (p_value < 0.001) return "***";
  if (p_value < 0.01) return "**";
  if (p_value < 0.05) return "*";
  return "";
}

}  // namespace fovlab::analysis
