#include "study/psychometric/psychometric_function.h"

#include <cmath>

#include "study/psychometric/psychometric_detail.h"

namespace fovlab {

const char* shape_name(PsychometricShape shape) {
  switch (shape) {
    case PsychometricShape::logistic:
      return "logistic";
    case PsychometricShape::weibull:
      return "weibull";
    case PsychometricShape::cumulative_normal:
      return "cumulative_normal";
  }
  return "unknown";
}

namespace detail {

namespace {

// 1 / (1 + exp(-x)) and its complement 1 / (1 + exp(x)), each without overflow and without
// cancellation: exp is only ever taken of a non-positive number.
SeeProbabilities logistic_pair(double x) {
  if (x >= 0.0) {
    const double e = std::exp(-x);  // in (0, 1]
    return {1.0 / (1.0 + e), e / (1.0 + e)};
  }
  const double e = std::exp(x);
  return {e / (1.0 + e), 1.0 / (1.0 + e)};
}

// Phi(x) = erfc(-x / sqrt 2) / 2 and 1 - Phi(x) = erfc(x / sqrt 2) / 2: erfc keeps full relative
// precision in both tails, where 1 - erf would cancel.
SeeProbabilities normal_pair(double x) {
  constexpr double kInvSqrt2 = 0.70710678118654752440;
  return {0.5 * std::erfc(-x * kInvSqrt2), 0.5 * std::erfc(x * kInvSqrt2)};
}

}  // namespace

SeeProbabilities see_probabilities(const PsychometricModel& model, double level) {
  const PsychometricParameters& q = model.parameters;
  switch (model.shape) {
    case PsychometricShape::logistic:
    case PsychometricShape::cumulative_normal: {
      const double x = (model.rising ? 1.0 : -1.0) * q.slope * (level - q.threshold);
      return model.shape == PsychometricShape::logistic ? logistic_pair(x) : normal_pair(x);
    }
    case PsychometricShape::weibull: {
      SeeProbabilities rising{0.0, 1.0};  // the limit at level <= 0
      if (level > 0.0) {
        // z = ln 2 * (level / threshold)^slope, taken through logs: a huge ratio gives z = inf,
        // hence exp(-z) = 0, and never a NaN.
        constexpr double kLn2 = 0.69314718055994530942;
        const double z = kLn2 * std::exp(q.slope * std::log(level / q.threshold));
        rising = {-std::expm1(-z), std::exp(-z)};  // 1 - exp(-z) without cancellation for small z
      }
      if (model.rising) return rising;
      return {rising.not_see, rising.see};
    }
  }
  return {std::nan(""), std::nan("")};
}

ReportProbabilities report_probabilities(const PsychometricModel& model, double level) {
  const SeeProbabilities see = see_probabilities(model, level);
  const double gain = 1.0 - model.guess - model.parameters.lapse;
  // p = guess + gain * see and 1 - p = lapse + gain * (1 - see): both sums of non-negative terms,
  // so a p_report next to 1 keeps its complement to full relative precision.
  return {model.guess + gain * see.see, model.parameters.lapse + gain * see.not_see};
}

}  // namespace detail

double PsychometricModel::p_see(double level) const { return detail::see_probabilities(*this, level).see; }

double PsychometricModel::p_report(double level) const { return detail::report_probabilities(*this, level).report; }

double visible_degradation(double see_logit) {
  const double a = see_logit;
  return a > 0.0 ? a + std::log1p(std::exp(-a)) : std::log1p(std::exp(a));  // softplus, without overflow
}

double step_seen_probability(double visible_degradation_before, double visible_degradation_after) {
  return -std::expm1(-std::fabs(visible_degradation_after - visible_degradation_before));
}

}  // namespace fovlab
