#pragma once
// Maximum-likelihood fits of a psychometric function (psychometric_function.h) to counts per level,
// with the guess rate fixed and the lapse rate free in [0, max_lapse]; profile-likelihood intervals
// (which always contain the estimate), and a seeded parametric bootstrap for percentile intervals
// and a goodness-of-fit p-value (Wichmann & Hill 2001).
#include <cstdint>
#include <string>
#include <vector>

#include "study/psychometric/psychometric_function.h"

namespace fovlab::analysis {

struct LevelCounts {
  double level = 0.0;
  uint64_t n = 0;  // trials at this level (>= 1)
  uint64_t k = 0;  // trials where a difference was reported (<= n)
};

struct FitOptions {
  PsychometricShape shape = PsychometricShape::logistic;
  bool rising = true;
  double guess = 0.0;            // fixed, in [0, 1)
  double max_lapse = 0.1;        // lapse is fitted in [0, max_lapse]
  int bootstrap_samples = 1000;  // 0: no bootstrap (intervals are NaN)
  uint64_t seed = 0;             // bootstrap replicate b draws from Pcg32(derive_seed(seed, b))
  double confidence = 0.95;      // of the profile-likelihood and the percentile intervals
};

struct ParameterInterval {
  double lower = 0.0;  // NaN: not computed (a bootstrap interval without a bootstrap)
  double upper = 0.0;  // an end the data do not bound is infinite (see the fit's note)
};

struct PsychometricFit {
  PsychometricModel model;        // the maximum-likelihood fit
  double log_likelihood = 0.0;    // binomial log likelihood, with the binomial coefficients
  double deviance = 0.0;          // 2 * (log L of the saturated model - log L of the fit), >= 0
  int degrees_of_freedom = 0;     // levels - 3 (may be <= 0: then the deviance says nothing)
  double deviance_p_value = 0.0;  // share of bootstrap deviances >= the fit's (NaN without bootstrap)
  // Profile-likelihood intervals at `confidence` (docs/analysis.md): the values the likelihood-ratio
  // test does not reject against the fit (chi-square, 1 degree of freedom), so they contain the
  // estimate by construction. An end the data do not bound within the search box is -infinity or
  // +infinity (the Weibull threshold and the slope: 0 below); the lapse's ends stay in [0, max_lapse].
  ParameterInterval threshold_interval;
  ParameterInterval slope_interval;
  ParameterInterval lapse_interval;
  // The parametric bootstrap's percentile intervals at `confidence` (NaN without bootstrap). They
  // can exclude the estimate when the replicates' fits are biased (e.g. a step between two levels).
  ParameterInterval bootstrap_threshold_interval;
  ParameterInterval bootstrap_slope_interval;
  ParameterInterval bootstrap_lapse_interval;
  int bootstrap_samples = 0;   // replicates whose fit converged (used for the intervals)
  int bootstrap_failures = 0;  // replicates whose fit did not converge
  bool converged = false;
  std::string note;  // why a fit is unreliable ("all levels at ceiling", ...), or ""
};

// Throws std::invalid_argument for empty data, n == 0, k > n, non-finite levels, a Weibull with a
// level <= 0, or options out of range. Needs at least two distinct levels.
PsychometricFit fit_psychometric(const std::vector<LevelCounts>& data, const FitOptions& options);

// Adds `text` to a note, after "; " when it has some already: the one format of the analysis's
// notes (fits, thresholds).
void append_note(std::string& note, const std::string& text);

}  // namespace fovlab::analysis
