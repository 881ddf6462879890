#pragma once
// From a study's data to its results: per-condition counts with exact binomial tests, Clopper-
// Pearson intervals and Holm correction; thresholds per protocol (Polychronakis et al. 2023 4.4/5.1, Polychronakis et al. 2021 4.7,
// Ye et al. 2022 4.4/5.2); psychometric fits with bootstrap intervals. Definitions in docs/analysis.md.
#include <cstdint>
#include <optional>
#include <vector>

#include "study/psychometric/psychometric_function.h"
#include "analysis/study/analysis_result.h"
#include "analysis/study/study_data.h"

namespace fovlab::analysis {

struct AnalysisOptions {
  Alternative alternative = Alternative::two_sided;
  double alpha = 0.05;
  std::optional<double> guess_rate;  // the fits' fixed guess rate; default by protocol (docs)
  int bootstrap_samples = 1000;
  uint64_t seed = 1;           // of the bootstrap
  double rating_cutoff = 2.0;  // Ye et al. 2022: the lowest mean score still acceptable
  std::vector<PsychometricShape> shapes = {PsychometricShape::logistic, PsychometricShape::weibull,
                                           PsychometricShape::cumulative_normal};
};

AnalysisResult analyse_study(const StudyData& data, const AnalysisOptions& options);

}  // namespace fovlab::analysis
