#pragma once
// One headline per (scene, variant) group (docs/analysis.md, "The headline"): the number a study
// hands back, by the method its design calls for, with a status that says whether it can be
// published as it stands.
//
//   constant stimuli (2afc same, pair)  the first psychometric fit's threshold, 95 % profile interval
//   adaptive blocks                     the mean of the participants' track estimates, 95 % Student-t
//                                       interval across participants; the pooled fit beside it
//   ramp                                the step model's threshold (ramp_model.h), bootstrap over participants
//   slider                              the mean of the participants' mean saved levels, Student-t interval
//   rating                              Ye et al. 2022's rule, bootstrap interval over participants
//   2afc "better"                       the share of trials the reference was preferred, Clopper-Pearson
//
// Not estimable: a threshold outside the tested levels, an interval that is unbounded or of zero
// width, a fit that did not converge, fewer than two participants where the interval is across
// participants. A lapse or slope at its search bound is a flag, not a failure.
#include <vector>

#include "analysis/study/analysis_result.h"
#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"

namespace fovlab::analysis {

// `result`: the analysis so far (conditions, thresholds, fits, participants with their tracks).
std::vector<Headline> study_headlines(const StudyData& data, const AnalysisOptions& options,
                                      const AnalysisResult& result);

// Why a psychometric fit's threshold cannot be published (""; it can): no convergence, outside
// the tested levels [low, high], an unbounded or zero-width interval.
std::string fit_not_estimable_reason(const PsychometricFit& fit, double low, double high);

}  // namespace fovlab::analysis
