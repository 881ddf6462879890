#include "study/schedule/quest_plus.h"

#include <algorithm>
#include <cmath>

#include "core/number_text.h"
#include "study/psychometric/psychometric_detail.h"

namespace fovlab {
namespace {

constexpr double kLn2 = 0.69314718055994530942;

std::vector<double> spaced(double low, double high, int count, bool logarithmic) {
  std::vector<double> values;
  for (int i = 0; i < count; ++i) {
    const double t = count > 1 ? double(i) / double(count - 1) : 0.0;
    values.push_back(logarithmic ? std::exp(std::log(low) + t * (std::log(high) - std::log(low)))
                                 : low + t * (high - low));
  }
  return values;
}

bool ascending(const std::vector<double>& values) {
  for (size_t i = 1; i < values.size(); ++i)
    if (!(values[i] > values[i - 1])) return false;
  return true;
}

// The threshold prior's weight (unnormalised) at each grid threshold.
std::vector<double> threshold_prior(const QuestPlusRule& rule) {
  std::vector<double> weights;
  for (double threshold : rule.thresholds) {
    const double z = rule.prior_sd > 0 ? (threshold - rule.prior_mean) / rule.prior_sd : 0.0;
    weights.push_back(std::exp(-0.5 * z * z));
  }
  return weights;
}

// sum of w log w over the non-zero entries, in nats (the entropy is its negative).
double entropy_nats(const std::vector<double>& posterior) {
  double sum = 0.0;
  for (double w : posterior)
    if (w > 0) sum -= w * std::log(w);
  return sum;
}

}  // namespace

std::vector<double> default_quest_thresholds(const std::vector<double>& levels, PsychometricShape shape) {
  const auto [low, high] = std::minmax_element(levels.begin(), levels.end());
  return spaced(*low, *high, 41, shape == PsychometricShape::weibull);
}

std::vector<double> default_quest_slopes(const std::vector<double>& levels, PsychometricShape shape) {
  if (shape == PsychometricShape::weibull) return spaced(1.0, 10.0, 8, true);
  const auto [low, high] = std::minmax_element(levels.begin(), levels.end());
  const double range = *high - *low;
  // The 10 %-90 % transition of p_see is 2 ln 9 / slope (logistic) or 2 * 1.2816 / slope (normal).
  const double width_times_slope =
      shape == PsychometricShape::logistic ? 2.0 * std::log(9.0) : 2.0 * 1.2815515655446004;
  return spaced(width_times_slope / range, width_times_slope * 20.0 / range, 8, true);
}

std::vector<double> default_quest_lapses() { return {0.0, 0.02, 0.04}; }

std::optional<std::string> quest_plus_rule_error(const QuestPlusRule& rule, const std::vector<double>& levels) {
  if (levels.size() < 2) return "levels: expected at least two levels for QUEST+";
  if (levels.size() > kQuestPlusMaxLevels)
    return "levels: expected at most " + std::to_string(kQuestPlusMaxLevels) + " levels for QUEST+, got " +
           std::to_string(levels.size());
  if (rule.shape == PsychometricShape::weibull && *std::min_element(levels.begin(), levels.end()) <= 0)
    return "shape: a Weibull function needs levels above 0";
  const auto grid_error = [](const char* key, const std::vector<double>& values) -> std::optional<std::string> {
    if (values.empty() || !ascending(values)) return std::string(key) + ": expected one or more values, ascending";
    return std::nullopt;
  };
  if (auto error = grid_error("thresholds", rule.thresholds)) return error;
  if (auto error = grid_error("slopes", rule.slopes)) return error;
  if (auto error = grid_error("lapses", rule.lapses)) return error;
  const size_t parameters = rule.thresholds.size() * rule.slopes.size() * rule.lapses.size();
  if (parameters > kQuestPlusMaxParameters)
    return "thresholds: expected at most " + std::to_string(kQuestPlusMaxParameters) +
           " (thresholds x slopes x lapses) grid points, got " + std::to_string(parameters);
  const auto [lowest, highest] = std::minmax_element(levels.begin(), levels.end());
  const double reach = kQuestPlusThresholdReach * (*highest - *lowest);
  if (rule.thresholds.front() < *lowest - reach || rule.thresholds.back() > *highest + reach)
    return "thresholds: expected values from " + format_number(*lowest - reach, 6) + " to " +
           format_number(*highest + reach, 6) + " (the levels' range, " + exact_number_text(*lowest) + " to " +
           exact_number_text(*highest) + ", widened by " + format_number(kQuestPlusThresholdReach, 6) +
           " times its span on each side), got " +
           exact_number_text(rule.thresholds.front() < *lowest - reach ? rule.thresholds.front()
                                                                       : rule.thresholds.back());
  if (rule.slopes.front() <= 0) return "slopes: expected values above 0";
  if (rule.shape == PsychometricShape::weibull && rule.thresholds.front() <= 0)
    return "thresholds: expected values above 0 (a Weibull function)";
  if (!(rule.guess >= 0 && rule.guess < 1)) return "guess_rate: expected a value in [0, 1)";
  if (rule.lapses.front() < 0 || rule.guess + rule.lapses.back() >= 1)
    return "lapses: expected values of at least 0 with guess_rate + lapse below 1 (room for p_see)";
  if (rule.prior_sd < 0) return "prior_sd: expected 0 (a uniform prior) or more";
  if (rule.prior_sd > 0) {
    const std::vector<double> weights = threshold_prior(rule);
    if (*std::max_element(weights.begin(), weights.end()) < 1e-12)
      return "prior_mean: expected a prior with mass on the threshold grid (" +
             format_number(rule.thresholds.front(), 6) + " to " + format_number(rule.thresholds.back(), 6) +
             "); a normal of mean " + format_number(rule.prior_mean, 6) + " and SD " + format_number(rule.prior_sd, 6) +
             " has none there";
  }
  if (rule.max_trials < 1) return "max_trials: expected 1 or more";
  const double max_entropy_bits = std::log2(double(parameters));
  if (rule.stop_entropy_bits < 0 || (rule.stop_entropy_bits > 0 && rule.stop_entropy_bits >= max_entropy_bits))
    return "stop_entropy_bits: expected 0 (none) or a value in (0, " + format_number(max_entropy_bits, 4) +
           ") bits (the uniform posterior's entropy; at or above it the procedure would stop before its first trial)";
  if (rule.stop_interval_width < 0 ||
      (rule.stop_interval_width > 0 && rule.stop_interval_width >= rule.thresholds.back() - rule.thresholds.front()))
    return "stop_interval_width: expected 0 (none) or a width below the threshold grid's range (" +
           format_number(rule.thresholds.back() - rule.thresholds.front(), 6) + ")";
  return std::nullopt;
}

QuestPlus::QuestPlus(QuestPlusRule rule, std::vector<double> levels)
    : rule_(std::move(rule)), levels_(std::move(levels)) {
  parameters_ = rule_.thresholds.size() * rule_.slopes.size() * rule_.lapses.size();
  seen_.resize(levels_.size() * parameters_);
  log_seen_.resize(seen_.size());
  log_not_seen_.resize(seen_.size());
  PsychometricModel model;
  model.shape = rule_.shape;
  model.rising = rule_.rising;
  model.guess = rule_.guess;
  for (size_t x = 0; x < levels_.size(); ++x) {
    size_t p = 0;
    for (double threshold : rule_.thresholds)
      for (double slope : rule_.slopes)
        for (double lapse : rule_.lapses) {
          model.parameters = {threshold, slope, lapse};
          const detail::ReportProbabilities probabilities = detail::report_probabilities(model, levels_[x]);
          const size_t at = x * parameters_ + p++;
          seen_[at] = probabilities.report;
          // log 0 is never used: its term is multiplied by the 0 likelihood.
          log_seen_[at] = probabilities.report > 0 ? std::log(probabilities.report) : 0.0;
          log_not_seen_[at] = probabilities.not_report > 0 ? std::log(probabilities.not_report) : 0.0;
        }
  }
}

QuestPlusState QuestPlus::start() const {
  QuestPlusState state;
  const std::vector<double> prior = threshold_prior(rule_);
  const size_t per_threshold = rule_.slopes.size() * rule_.lapses.size();
  double total = 0.0;
  for (size_t t = 0; t < rule_.thresholds.size(); ++t)
    for (size_t i = 0; i < per_threshold; ++i) {
      state.posterior.push_back(prior[t]);
      total += prior[t];
    }
  for (double& w : state.posterior) w /= total;
  state.index = choose(state.posterior);
  return state;
}

std::vector<double> QuestPlus::expected_entropies(const std::vector<double>& posterior) const {
  std::vector<double> log_w(parameters_);
  for (size_t p = 0; p < parameters_; ++p) log_w[p] = posterior[p] > 0 ? std::log(posterior[p]) : 0.0;
  std::vector<double> entropies;
  for (size_t x = 0; x < levels_.size(); ++x) {
    const double* seen = &seen_[x * parameters_];
    const double* log_seen = &log_seen_[x * parameters_];
    const double* log_not_seen = &log_not_seen_[x * parameters_];
    double a_seen = 0.0, b_seen = 0.0, a_not = 0.0, b_not = 0.0;
    for (size_t p = 0; p < parameters_; ++p) {
      const double w_seen = posterior[p] * seen[p];
      const double w_not = posterior[p] - w_seen;
      a_seen += w_seen;
      b_seen += w_seen * (log_w[p] + log_seen[p]);
      a_not += w_not;
      b_not += w_not * (log_w[p] + log_not_seen[p]);
    }
    double expected = -b_seen - b_not;
    if (a_seen > 0) expected += a_seen * std::log(a_seen);
    if (a_not > 0) expected += a_not * std::log(a_not);
    entropies.push_back(expected);
  }
  return entropies;
}

int QuestPlus::choose(const std::vector<double>& posterior) const {
  const std::vector<double> entropies = expected_entropies(posterior);
  return static_cast<int>(std::min_element(entropies.begin(), entropies.end()) - entropies.begin());
}

QuestPlusState QuestPlus::next(QuestPlusState state, bool seen) const {
  if (state.finished) return state;
  ++state.trials;
  const double* likelihood = &seen_[static_cast<size_t>(state.index) * parameters_];
  std::vector<double> posterior(parameters_);
  double total = 0.0;
  for (size_t p = 0; p < parameters_; ++p) {
    posterior[p] = state.posterior[p] * (seen ? likelihood[p] : 1.0 - likelihood[p]);
    total += posterior[p];
  }
  // An answer every grid point calls impossible (possible only with guess and lapses of 0) leaves
  // the posterior as it was.
  if (total > 0) {
    for (double& w : posterior) w /= total;
    state.posterior = std::move(posterior);
  }
  state.finished = state.trials >= rule_.max_trials;
  if (!state.finished && (rule_.stop_entropy_bits > 0 || rule_.stop_interval_width > 0)) {
    // The estimate only for a stopping rule that needs it (a pass over the posterior each answer).
    const QuestPlusEstimate estimate = this->estimate(state.posterior);
    state.finished = (rule_.stop_entropy_bits > 0 && estimate.entropy_bits <= rule_.stop_entropy_bits) ||
                     (rule_.stop_interval_width > 0 &&
                      estimate.threshold_upper - estimate.threshold_lower <= rule_.stop_interval_width);
  }
  if (!state.finished) state.index = choose(state.posterior);
  return state;
}

QuestPlusState QuestPlus::replay(const std::vector<bool>& answers) const {
  QuestPlusState state = start();
  for (const bool seen : answers) state = next(std::move(state), seen);
  return state;
}

QuestPlusEstimate QuestPlus::estimate(const std::vector<double>& posterior) const {
  QuestPlusEstimate estimate;
  const size_t slopes = rule_.slopes.size(), lapses = rule_.lapses.size();
  std::vector<double> marginal(rule_.thresholds.size(), 0.0);
  size_t p = 0;
  for (size_t t = 0; t < rule_.thresholds.size(); ++t)
    for (size_t s = 0; s < slopes; ++s)
      for (size_t l = 0; l < lapses; ++l) {
        const double w = posterior[p++];
        marginal[t] += w;
        estimate.threshold_mean += w * rule_.thresholds[t];
        estimate.slope_mean += w * rule_.slopes[s];
        estimate.lapse_mean += w * rule_.lapses[l];
      }
  double cumulative = 0.0;
  bool lower_found = false, upper_found = false;
  for (size_t t = 0; t < marginal.size(); ++t) {
    cumulative += marginal[t];
    if (!lower_found && cumulative >= 0.025) {
      estimate.threshold_lower = rule_.thresholds[t];
      lower_found = true;
    }
    if (!upper_found && cumulative >= 0.975) {
      estimate.threshold_upper = rule_.thresholds[t];
      upper_found = true;
    }
  }
  if (!upper_found) estimate.threshold_upper = rule_.thresholds.back();  // rounding left the sum short of 0.975
  if (!lower_found) estimate.threshold_lower = rule_.thresholds.back();
  estimate.entropy_bits = entropy_nats(posterior) / kLn2;
  return estimate;
}

}  // namespace fovlab
