#pragma once
// Psychometric functions: the probability that an observer reports a difference between a test
// stimulus at `level` and its reference,
//
//   p_report(level) = guess + (1 - guess - lapse) * p_see(level)
//
// with p_see a sigmoid from 0 to 1 whose `threshold` is the level where p_see = 1/2 and whose
// `slope` sets its steepness (> 0). `rising`: p_see grows with the level (the difference grows with
// it); otherwise it falls (e.g. foveal eccentricity: larger levels look more like the reference).
//   logistic:          p_see = 1 / (1 + exp(-s * slope * (level - threshold)))
//   cumulative normal: p_see = Phi(s * slope * (level - threshold))           (slope = 1 / sigma)
//   Weibull (levels > 0 only):
//     rising:  p_see = 1 - exp(-ln 2 * (level / threshold)^slope)
//     falling: p_see =     exp(-ln 2 * (level / threshold)^slope)
// where s = +1 when rising and -1 when falling. Definitions in docs/analysis.md.
#include <string>

namespace fovlab {

enum class PsychometricShape { logistic, weibull, cumulative_normal };

const char* shape_name(PsychometricShape shape);  // "logistic", "weibull", "cumulative_normal"

struct PsychometricParameters {
  double threshold = 0.0;  // level where p_see = 1/2 (Weibull: > 0)
  double slope = 1.0;      // > 0
  double lapse = 0.0;      // in [0, 1 - guess)
};

struct PsychometricModel {
  PsychometricShape shape = PsychometricShape::logistic;
  bool rising = true;
  double guess = 0.0;  // fixed: the rate of reporting a difference where none can be seen
  PsychometricParameters parameters;

  double p_see(double level) const;     // in [0, 1]; Weibull at level <= 0: the limit (0 rising, 1 falling)
  double p_report(double level) const;  // guess + (1 - guess - lapse) * p_see
};

// How a step between two stimuli is seen (docs/analysis.md, "Ramp: the step model"): a stimulus
// whose logit of p_see against the reference is `see_logit` (positive on the degraded side) carries
// the visible degradation softplus(see_logit), 0 for the reference; a step between two stimuli of
// visible degradations a and b is seen with probability 1 - exp(-|a - b|), which against the
// reference is the logistic p_see itself. The simulated observer answers ramps by it and the
// analysis fits it (analysis/study/ramp_model.h).
double visible_degradation(double see_logit);
double step_seen_probability(double visible_degradation_before, double visible_degradation_after);

}  // namespace fovlab
