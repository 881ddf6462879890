#pragma once
// Ye et al. 2022's pilot study (sections 4.3.1 and 4.4.1, Figure 9): participants rate the test stimulus
// against the reference (3 identical, 2 a minimal difference, 1 a significant difference) for every
// pair of two test parameters on a grid (f_x, f_y), at several levels (sigma). Per block, and over
// every block pooled, the mean score of each pair over the levels and the participants, and the pair
// with the highest mean (f_x*, f_y*). Definitions in docs/analysis.md ("Pilot grid").
#include <optional>
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"
#include "analysis/study/study_data.h"

namespace fovlab::analysis {

// The two parameters a study's variants set on a full grid, and where each variant lies on it.
struct ParameterGrid {
  std::string x_key;  // alphabetical order: x before y
  std::string y_key;
  std::vector<double> x_values;  // ascending, at least two each
  std::vector<double> y_values;
  std::vector<size_t> cell_of_variant;  // per variant (config order): its cell, row * x_values.size() + column
};

// The grid the variants form, or none. They form one when every variant sets the same keys, exactly
// two of those keys take more than one value (the others one value throughout), both are integer or
// real parameters of the test method (not a choice) other than the levels' parameter, each takes at
// least two values, and every (x, y) pair of those values is set by exactly one variant.
std::optional<ParameterGrid> find_parameter_grid(RenderMethod test_method, const std::string& level_parameter,
                                                 const std::vector<VariantConfig>& variants);

// The grid's maps from the answered rating trials of the included participants (attention checks,
// timeouts and excluded participants are not counted); none when the study is not a rating study
// or its variants form no grid.
std::optional<RatingGrid> rating_grid(const StudyData& data);

}  // namespace fovlab::analysis
