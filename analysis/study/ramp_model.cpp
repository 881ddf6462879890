#include "analysis/study/ramp_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "analysis/fitting/nelder_mead.h"
#include "analysis/statistics/percentile.h"
#include "core/prng.h"
#include "study/psychometric/psychometric_function.h"

namespace fovlab::analysis {
namespace {

constexpr double kMaxLapse = 0.1;

// A stimulus's visible degradation (study/psychometric/psychometric_function.h); 0 for the reference.
double degradation_of(std::optional<double> level, double threshold, double slope, bool higher_is_better) {
  return level ? visible_degradation(slope * (higher_is_better ? threshold - *level : *level - threshold)) : 0.0;
}

// Steps with the same stimuli and answer counted once with a weight: the likelihood visits each
// distinct step, not each answer.
struct WeightedStep {
  std::optional<double> before, after;
  double right = 0.0, same = 0.0;  // counts; a wrong-way answer adds only a constant to the likelihood
};

std::vector<WeightedStep> weigh(const std::vector<RampStep>& steps, const std::vector<int>& participant_weight) {
  std::vector<WeightedStep> weighted;
  for (const RampStep& step : steps) {
    const double w = double(participant_weight[size_t(step.participant)]);
    if (w == 0.0 || step.answer == RampStep::Answer::wrong) continue;
    auto found = std::find_if(weighted.begin(), weighted.end(),
                              [&](const WeightedStep& s) { return s.before == step.before && s.after == step.after; });
    if (found == weighted.end()) {
      weighted.push_back({step.before, step.after});
      found = weighted.end() - 1;
    }
    (step.answer == RampStep::Answer::right ? found->right : found->same) += w;
  }
  return weighted;
}

struct Solution {
  detail::Point x{};
  double f = std::numeric_limits<double>::infinity();
  bool converged = false;
};

// x = (T, log S, lapse): the negative log likelihood of the right and "same" answers.
Solution fit(const std::vector<WeightedStep>& steps, double guess, bool higher_is_better, double low, double high,
             const std::vector<detail::Point>& starts) {
  const double range = std::max(high - low, 1e-9);
  const auto objective = [&](const detail::Point& x) {
    const double slope = std::exp(x[1]);
    double nll = 0.0;
    for (const WeightedStep& step : steps) {
      const double p = ramp_step_seen_probability(step.before, step.after, x[0], slope, higher_is_better);
      const double p_right = (1.0 - guess - x[2]) * p + 0.5 * guess;
      const double p_same = 1.0 - guess - (1.0 - guess - x[2]) * p;
      if (step.right > 0) nll -= step.right * std::log(std::max(p_right, 1e-300));
      if (step.same > 0) nll -= step.same * std::log(std::max(p_same, 1e-300));
    }
    return nll;
  };
  detail::NelderMeadSettings settings;
  settings.dimensions = 3;
  settings.lower = {low - range, std::log(0.1 / range), 0.0};
  settings.upper = {high + range, std::log(1000.0 / range), kMaxLapse};
  settings.initial_step = {0.1 * range, 0.5, 0.02};
  settings.x_tolerance = 1e-7 * std::max(1.0, range);
  Solution best;
  for (const detail::Point& start : starts) {
    const detail::NelderMeadResult result = detail::nelder_mead(objective, start, settings);
    if (result.f < best.f) best = {result.x, result.f, result.converged};
  }
  return best;
}

}  // namespace

double ramp_step_seen_probability(std::optional<double> before, std::optional<double> after, double threshold,
                                  double slope, bool higher_is_better) {
  return step_seen_probability(degradation_of(before, threshold, slope, higher_is_better),
                               degradation_of(after, threshold, slope, higher_is_better));
}

RampModelFit fit_ramp_model(const std::vector<RampStep>& steps, bool higher_is_better, double level_low,
                            double level_high, int bootstrap_samples, uint64_t seed) {
  RampModelFit result;
  result.steps = steps.size();
  int participants = 0;
  size_t wrong = 0;
  for (const RampStep& step : steps) {
    participants = std::max(participants, step.participant + 1);
    wrong += step.answer == RampStep::Answer::wrong ? 1 : 0;
  }
  result.participants = participants;
  if (steps.empty()) {
    result.note = "no answered ramp step";
    return result;
  }
  // A guess goes either way: the wrong-way share is half the guess rate.
  result.guess = std::min(0.5, 2.0 * double(wrong) / double(steps.size()));
  const double range = std::max(level_high - level_low, 1e-9);
  std::vector<detail::Point> starts;
  for (double t : {0.1, 0.3, 0.5, 0.7, 0.9})
    for (double scaled_slope : {2.0, 8.0, 32.0})
      starts.push_back({level_low + t * range, std::log(scaled_slope / range), 0.02});
  const std::vector<int> everyone(size_t(participants), 1);
  const Solution best = fit(weigh(steps, everyone), result.guess, higher_is_better, level_low, level_high, starts);
  result.converged = best.converged;
  result.threshold = best.x[0];
  result.slope = std::exp(best.x[1]);
  result.lapse = best.x[2];
  if (!result.converged) result.note = "the step model's fit did not converge";
  if (bootstrap_samples <= 0 || participants < 2) return result;
  std::vector<double> thresholds;
  for (int b = 0; b < bootstrap_samples; ++b) {
    Pcg32 random(derive_seed(seed, uint64_t(b)));
    std::vector<int> weight(size_t(participants), 0);
    for (int i = 0; i < participants; ++i) ++weight[random.below(uint32_t(participants))];
    // Guess and lapse of the replicate's own steps; one start: the whole data's fit.
    size_t replicate_steps = 0, replicate_wrong = 0;
    for (const RampStep& step : steps) {
      replicate_steps += size_t(weight[size_t(step.participant)]);
      replicate_wrong += step.answer == RampStep::Answer::wrong ? size_t(weight[size_t(step.participant)]) : 0;
    }
    const double guess = std::min(0.5, 2.0 * double(replicate_wrong) / double(std::max<size_t>(1, replicate_steps)));
    const Solution replicate = fit(weigh(steps, weight), guess, higher_is_better, level_low, level_high, {best.x});
    if (replicate.converged) thresholds.push_back(replicate.x[0]);
  }
  result.bootstrap_samples = int(thresholds.size());
  if (thresholds.size() >= 20) {
    result.lower = nearest_rank_percentile(thresholds, 2.5);
    result.upper = nearest_rank_percentile(thresholds, 97.5);
  } else {
    result.note +=
        std::string(result.note.empty() ? "" : "; ") + "too few bootstrap replicates converged for an interval";
  }
  return result;
}

}  // namespace fovlab::analysis
