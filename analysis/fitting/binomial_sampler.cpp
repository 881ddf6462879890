#include "analysis/fitting/binomial_sampler.h"

#include <boost/math/distributions/binomial.hpp>
#include <boost/math/policies/policy.hpp>

#include <cmath>
#include <stdexcept>

namespace fovlab::analysis {

namespace {

using QuantilePolicy =
    boost::math::policies::policy<boost::math::policies::discrete_quantile<boost::math::policies::integer_round_up>>;
using BinomialDistribution = boost::math::binomial_distribution<double, QuantilePolicy>;

constexpr uint64_t kBernoulliLimit = 64;

}  // namespace

uint64_t draw_binomial(uint64_t n, double p, Pcg32& rng) {
  if (std::isnan(p)) throw std::invalid_argument("draw_binomial: p is NaN");
  if (n == 0 || p <= 0.0) return 0;
  if (p >= 1.0) return n;
  if (n <= kBernoulliLimit) {
    uint64_t k = 0;
    for (uint64_t i = 0; i < n; ++i) k += rng.uniform() < p ? 1 : 0;
    return k;
  }
  const double u = rng.uniform();  // [0, 1)
  const BinomialDistribution distribution(static_cast<double>(n), p);
  const double nd = static_cast<double>(n);
  double x = 0.0;
  if (u > 0.0) {
    x = boost::math::quantile(distribution, u);
    if (!(x >= 0.0)) x = 0.0;
    if (x > nd) x = nd;
  }
  // Make P(X <= x - 1) < u <= P(X <= x) hold against the CDF itself. Boost's answer is normally
  // already right, so these loops run zero or one time.
  while (x < nd && boost::math::cdf(distribution, x) < u) x += 1.0;
  while (x > 0.0 && boost::math::cdf(distribution, x - 1.0) >= u) x -= 1.0;
  return static_cast<uint64_t>(x);
}

}  // namespace fovlab::analysis
