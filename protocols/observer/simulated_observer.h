#pragma once
// A simulated observer for demos, pilots and tests: a psychometric model of how often a difference
// between a test stimulus and its reference is seen, and seeded answers derived from it.
//
//   p_see(x)    = logistic: 1 / (1 + exp(-slope * (x - threshold))), mirrored when higher levels are
//                 better (then p_see falls as x grows); identical stimuli: p_see = 0
//   p_detect(x) = guess + (1 - guess - lapse) * p_see(x)
//
// Ramps compare neighbouring stimuli, both possibly degraded, so the observer needs a magnitude, not
// only "seen or not": the visible degradation v(x) = softplus(a), a = the logit of p_see(x) (0 for
// the reference, about slope * |x - threshold| far on the degraded side, near 0 on the other), and
// a difference d between two stimuli is seen with probability 1 - exp(-d). Against the reference
// that is 1 - exp(-softplus(a)) = p_see(x) exactly, so the ramp observer and the comparison observer
// are one model; two clearly degraded neighbours 5 levels apart with slope 0.32 differ by 1.6 and
// are told apart 80 % of the time. A seen step is answered in its true direction; a guess (a false
// alarm) in either direction with equal chance; otherwise "same".
//
// guess is the false-alarm rate (a difference "seen" where there is none), lapse the rate of missing
// a difference that is plainly visible. Every answer of trial i, step s comes from its own PCG32
// stream derive_seed(seed, i, s), so a resumed or replayed session gets the same answers.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "study/schedule/study_plan.h"

namespace fovlab {

struct ObserverModel {
  double threshold = 0.0;  // level where p_see = 0.5
  double slope = 1.0;      // per level unit, > 0
  double guess = 0.02;
  double lapse = 0.02;
  double mean_response_s = 0.8;  // reaction time: 0.3 s + exponential with this mean minus 0.3 s
  uint64_t seed = 0;
  bool higher_is_better = true;

  double p_see(std::optional<double> level) const;  // nullopt: identical stimuli
  double p_detect(std::optional<double> level) const;
  double visible_degradation(std::optional<double> level) const;  // v(x) above; 0 for nullopt
};

// "simulated" or "simulated:threshold=7.5,slope=1,guess=0.02,lapse=0.02,rt=0.8,seed=3". Defaults:
// threshold at the middle of the study's levels (0 without levels), slope 8 / (level range), seed
// derived from the session seed. Throws InputError naming the bad key.
ObserverModel parse_observer_spec(const std::string& text, const StudyPlan& plan);

struct ObserverAnswer {
  std::string answer;
  double response_time_s = 0.0;
};

class SimulatedObserver {
 public:
  SimulatedObserver(ObserverModel model, const StudyPlan& plan) : model_(model), plan_(plan) {}
  const ObserverModel& model() const { return model_; }
  const StudyPlan& plan() const { return plan_; }

  // Comparison trials (2afc, pair, rating): one answer.
  ObserverAnswer answer_comparison(const Trial& trial) const;
  // Ramp: the answer after step `step` (>= 1) of the sequence.
  ObserverAnswer answer_ramp_step(const Trial& trial, int step) const;
  // Slider: the action `action` (0, 1, ...) with the ladder at index `ladder_index`.
  ObserverAnswer answer_slider(const Trial& trial, int action, int ladder_index) const;
  // Instructions: any key to begin.
  double instructions_time_s() const { return 2.0; }

 private:
  std::optional<double> level_of(int stimulus) const;
  const ObserverModel model_;
  const StudyPlan& plan_;
};

}  // namespace fovlab
