#pragma once
// Exact binomial inference on k successes in n trials, on Boost.Math's binomial distribution:
// the exact test (two-sided as R's binom.test and SciPy's binomtest, or one-sided), Clopper-Pearson
// intervals and significance stars. Definitions in docs/analysis.md ("Statistics").
//
// Every function is correct for k = 0, k = n, p0 = 0 or 1, and n up to 10^9 and beyond: the cost
// is O(log n) evaluations of the distribution, never a loop over n.
#include <cstdint>
#include <string>

namespace fovlab::analysis {

enum class Alternative { two_sided, greater, less };

const char* alternative_name(Alternative alternative);  // "two-sided", "greater", "less"
// "two-sided", "greater" or "less"; throws InputError("--alternative: ...") otherwise.
Alternative parse_alternative(const std::string& text);

// p-value of H0: success probability == p0 given k successes in n trials (k <= n,
// 1 <= n <= 2^53 - 1, 0 <= p0 <= 1; std::invalid_argument otherwise).
//   greater:   P(X >= k)
//   less:      P(X <= k)
//   two-sided: the probability of every outcome no more likely than k, with R's relative
//              tolerance: sum of P(X = i) over i with P(X = i) <= P(X = k) * (1 + 1e-7).
//              k == n p0 (in double precision) gives 1.
// p0 = 0 or 1 makes X certain (0 or n): each p-value is then 1 or 0. The result is clamped to [0, 1],
// and a p-value below kSmallestPrintedPValue is 0 (never a subnormal): binomial_test_log10_p_value
// gives its size.
double binomial_test_p_value(uint64_t k, uint64_t n, double p0, Alternative alternative);

// p-values below this are not printed as numbers: a double holds them only as subnormals (or 0),
// so fovlab gives log10 p beside them and prints "< 1e-300 (log10 p = -301029.7)".
constexpr double kSmallestPrintedPValue = 1e-300;

// log10 of binomial_test_p_value's p, summed in log space where the p-value is below
// kSmallestPrintedPValue (Debian's Boost 1.74 has no log-space binomial tail): the tails are summed
// outward from k, each term the previous times the ratio of neighbouring probabilities, the
// log-probability of k from lgamma. Equal to log10(binomial_test_p_value) elsewhere; -infinity
// where p is exactly 0 (p0 = 0 or 1).
double binomial_test_log10_p_value(uint64_t k, uint64_t n, double p0, Alternative alternative);

// A p-value as text: `significant_digits` digits, or "< 1e-300 (log10 p = -301029.7)" below
// kSmallestPrintedPValue (log10_p from binomial_test_log10_p_value).
std::string p_value_text(double p_value, double log10_p, int significant_digits);

struct ProportionInterval {
  double lower = 0.0;
  double upper = 1.0;
};

// Clopper-Pearson ("exact") two-sided interval for the success probability at the given confidence
// level (0 < confidence < 1): lower = 0 when k = 0, upper = 1 when k = n. Requires 1 <= n <= 2^53 - 1
// and k <= n (std::invalid_argument otherwise).
ProportionInterval clopper_pearson_interval(uint64_t k, uint64_t n, double confidence = 0.95);

// "***" for p < 0.001, "**" for p < 0.01, "*" for p < 0.05, "" otherwise (Ye et al. 2022, Table 2).
// A NaN p-value throws std::invalid_argument.
std::string significance_stars(double p_value);

}  // namespace fovlab::analysis
