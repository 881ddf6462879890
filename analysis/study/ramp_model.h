#pragma once
// A threshold from ramp step answers through a model of how a step is seen (docs/analysis.md,
// "Ramp: the step model"). Polychronakis et al. 2021's rule (the most degraded step answered
// wrongly) takes the extreme of many noisy answers, so a single miss between two visibly degraded
// stimuli moves it, and it lands below the observers' threshold (10.1 for a truth of 14). This
// estimator uses every step answer instead.
//
// The model: a stimulus at level x carries a visible degradation v(x) = softplus(a), a = S (T - x)
// when higher levels are better (S (x - T) otherwise), 0 for the reference; a step between two
// stimuli is seen with probability p = 1 - exp(-|v(after) - v(before)|), which against the
// reference is logistic(a): T is the level told from the reference half the time (p_see = 1/2,
// the threshold of the 2afc fits). A step is answered in its direction with (1 - g - l) p + g/2,
// the other way with g/2 (a guess), "same" otherwise; g is the share of steps answered the wrong
// way, doubled, and T, S and the lapse l in [0, 0.1] are fitted by maximum likelihood over the
// steps of every participant together. The 95 % interval is a percentile bootstrap over
// participants (a participant's steps resampled as a whole), so it carries how participants differ.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace fovlab::analysis {

struct RampStep {
  std::optional<double> before, after;  // the two stimuli's levels (none: the reference)
  enum class Answer { right, wrong, same } answer = Answer::same;
  int participant = 0;  // the bootstrap resamples participants by this index
};

struct RampModelFit {
  bool converged = false;
  double threshold = 0.0;  // T, in level units
  double slope = 0.0;      // S, per level unit
  double lapse = 0.0, guess = 0.0;
  size_t steps = 0;
  int participants = 0;
  std::optional<double> lower, upper;  // 95 % percentile bootstrap interval of T over participants
  int bootstrap_samples = 0;           // replicates that converged
  std::string note;
};

// `level_low`, `level_high`: the tested range (the search box spans it and one range either side).
// `bootstrap_samples` 0: no interval. Replicate b draws from Pcg32(derive_seed(seed, b)).
RampModelFit fit_ramp_model(const std::vector<RampStep>& steps, bool higher_is_better, double level_low,
                            double level_high, int bootstrap_samples, uint64_t seed);

// The probability that a step between `before` and `after` is seen, by the model above.
double ramp_step_seen_probability(std::optional<double> before, std::optional<double> after, double threshold,
                                  double slope, bool higher_is_better);

}  // namespace fovlab::analysis
