#pragma once
// Simulated participants for a study's procedures (issue 19; `fovlab simulate`): each participant's
// schedule (study/schedule) answered by the simulated observer (protocols/observer) through the
// session's own AdaptiveProgress, trial by trial, without rendering: the observer answers from the
// level alone, so frames would change nothing (a session's logged answers are the observer's, which
// replay checks). Per block, procedure and variant it reports the bias and spread of the estimated
// threshold against the level the procedure aims at, and the trials used.
//
// What each procedure estimates, and the truth it is held to:
//   constant stimuli  a maximum-likelihood logistic fit of the participant's counts (guess fixed at
//                     the observer's): the level where p_see = 1/2, the observer's threshold.
//   QUEST+            the posterior mean of its threshold: the level where p_see = 1/2.
//   staircase         the mean of the last reversals: it converges where p_report equals its
//                     target (0.5^(1/down), or easier / (harder + easier)), a different point of the
//                     same function; the truth is the level where the observer's p_report is that.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/study/analysis_result.h"
#include "study/config/study_config.h"

namespace fovlab::bench {

struct SimulationOptions {
  int participants = 100;
  std::string observer = "simulated";  // the observer spec of fovlab run --observer (without seed=: per participant)
  int threads = 0;                     // 0: every core
  // Each adaptive procedure's max_trials, once per value (empty: as the config says); constant
  // stimuli are simulated once.
  std::vector<int> max_trials;
};

struct ProcedureSummary {
  std::string block, procedure, variant;  // procedure "constant" for constant stimuli
  std::string kind;                       // "constant", "staircase", "quest_plus"
  int max_trials = 0;                     // the procedure's (adaptive only)
  double truth = 0.0;                     // the level the procedure aims at (see above); NaN outside the levels
  int participants = 0;
  int estimates = 0;  // participants with a threshold (a fit that converged, enough reversals)
  double mean_estimate = 0.0, bias = 0.0, sd = 0.0, rmse = 0.0;  // over the estimates
  double mean_trials = 0.0;                                      // trials a participant answered for it
};

// A pilot of the simulated participants, analysed as `fovlab analyze` would analyse their logs
// (analysis/study/headline.h), each group's headline beside what its method aims at for these
// observers: the observer's threshold (fits, QUEST+, the ramp's step model); the level where
// p_report is a staircase's target; the expected saved level (slider: from the start, a step up
// while a difference is seen); the most degraded level whose expected mean rating keeps the
// cutoff (rating); none for a preference share.
struct HeadlineCheck {
  analysis::Headline headline;
  double aim = 0.0;  // NaN: none
};

struct SimulationResult {
  std::vector<ProcedureSummary> summaries;  // in block, procedure, variant order
  std::vector<HeadlineCheck> headlines;     // of the first sweep (--max-trials' first value)
  double observer_threshold = 0.0, observer_slope = 0.0, observer_guess = 0.0, observer_lapse = 0.0;
  double wall_s = 0.0;
  int threads = 0;
};

// Throws InputError for an observer spec or participant count that cannot be used.
SimulationResult simulate_study(const StudyConfig& config, const SimulationOptions& options);

}  // namespace fovlab::bench
