#pragma once
// Internals of the psychometric fits shared by psychometric_function.cpp and psychometric_fit.cpp
// (and their tests): probabilities together with their complements, each computed without
// cancellation, so that log(1 - p) stays accurate where p is close to 1.
#include "study/psychometric/psychometric_function.h"

namespace fovlab::detail {

struct SeeProbabilities {
  double see = 0.0;      // p_see(level)
  double not_see = 1.0;  // 1 - p_see(level), computed directly
};

struct ReportProbabilities {
  double report = 0.0;      // p_report(level)
  double not_report = 1.0;  // 1 - p_report(level) = lapse + (1 - guess - lapse) * (1 - p_see)
};

SeeProbabilities see_probabilities(const PsychometricModel& model, double level);
ReportProbabilities report_probabilities(const PsychometricModel& model, double level);

}  // namespace fovlab::detail
