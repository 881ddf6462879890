#include "analysis/statistics/multiple_comparisons.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/number_text.h"

namespace fovlab::analysis {

std::vector<double> holm_adjusted(const std::vector<double>& p_values) {
  for (std::size_t i = 0; i < p_values.size(); ++i) {
    if (!(p_values[i] >= 0.0 && p_values[i] <= 1.0)) {
      throw std::invalid_argument("holm_adjusted: p-value " + std::to_string(i) + " (" +
                                  exact_number_text(p_values[i]) + ") is not in [0, 1]");
    }
  }
  const std::size_t m = p_values.size();
  // Ranks by ascending p; ties keep input order (any order of ties gives the same result).
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return p_values[a] < p_values[b]; });

  std::vector<double> adjusted(m);
  double running_max = 0.0;
  for (std::size_t rank = 0; rank < m; ++rank) {  // rank j = rank + 1 multiplies by m - j + 1
    const std::size_t index = order[rank];
    const double scaled = std::min(1.0, static_cast<double>(m - rank) * p_values[index]);
    running_max = std::max(running_max, scaled);
    adjusted[index] = running_max;
  }
  return adjusted;
}

}  // namespace fovlab::analysis
