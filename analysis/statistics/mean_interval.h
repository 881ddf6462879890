#pragma once
// The mean of a sample with its sample SD and 95 % Student-t interval (n - 1 degrees of freedom):
// the across-participant summary of per-participant thresholds (docs/analysis.md).
#include <optional>
#include <vector>

namespace fovlab::analysis {

struct MeanInterval {
  std::optional<double> mean;                    // none for no values
  std::optional<double> sd;                      // sample SD; none below two values
  std::optional<double> mean_lower, mean_upper;  // 95 % Student-t interval of the mean; none below two values
  int count = 0;
};

MeanInterval mean_with_t_interval(const std::vector<double>& values);

}  // namespace fovlab::analysis
