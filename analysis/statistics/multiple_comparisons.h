#pragma once
// Corrections for testing several conditions at once.
#include <vector>

namespace fovlab::analysis {

// Holm's step-down adjusted p-values (Holm 1979), in the order of the input: with the m p-values
// sorted ascending p(1) <= ... <= p(m), adjusted p(i) = max over j <= i of min(1, (m - j + 1) p(j)).
// Equal to R's p.adjust(p, "holm"). Rejecting every adjusted p < alpha controls the family-wise
// error rate at alpha. Every input must lie in [0, 1]: NaN or values outside throw
// std::invalid_argument. Empty input gives an empty result.
std::vector<double> holm_adjusted(const std::vector<double>& p_values);

}  // namespace fovlab::analysis
