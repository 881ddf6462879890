#pragma once
// Exact draws from Binomial(n, p) on the project's PRNG (core/prng.h), for the parametric
// bootstrap of psychometric fits. Definitions in docs/analysis.md ("Psychometric fits").
//
//   p <= 0: 0; p >= 1: n (no random numbers are used).
//   n <= 64: the number of i in [0, n) with rng.uniform() < p (n uniforms).
//   n > 64:  inversion of one uniform u = rng.uniform(): the integer x with
//            P(X <= x - 1) < u <= P(X <= x) (x = 0 when u <= P(X = 0)), where P is Boost.Math's
//            binomial CDF. Boost's discrete quantile (integer_round_up) gives the starting point
//            and the result is then checked and stepped against the CDF until the inequality
//            holds, so it is exact to the accuracy of the CDF, and costs O(1) CDF evaluations
//            (incomplete beta functions) whatever n is.
// The draws of a given (n, p) depend only on the state of `rng`.
#include <cstdint>

#include "core/prng.h"

namespace fovlab::analysis {

// Throws std::invalid_argument when p is NaN.
uint64_t draw_binomial(uint64_t n, double p, Pcg32& rng);

}  // namespace fovlab::analysis
