#include "analysis/study/headline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

#include "analysis/statistics/binomial.h"
#include "analysis/statistics/mean_interval.h"
#include "analysis/statistics/percentile.h"
#include "analysis/study/ramp_model.h"
#include "core/number_text.h"
#include "core/prng.h"
#include "study/schedule/staircase.h"

namespace fovlab::analysis {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

bool in_group(const std::string& scene, const std::string& variant, const GroupKey& group) {
  return variant == group.variant && (group.scene == scene || group.scene == "all");
}

std::string number(double value) { return format_number(value, 4); }

// "[a, b]", "(-inf, b]", ...; "" without an interval.
std::string interval_text(std::optional<double> lower, std::optional<double> upper) {
  return lower && upper ? format_interval(*lower, *upper, 4) : "";
}

// The interval is unbounded or of zero width: no value to publish ("": it is neither).
std::string interval_failure(double value, std::optional<double> lower, std::optional<double> upper,
                             const std::string& what) {
  if (!lower || !upper) return "";
  if (std::isinf(*lower) || std::isinf(*upper))
    return "its 95 % " + what + " " + interval_text(lower, upper) +
           " is unbounded: the data do not bound the threshold";
  if (*upper - *lower <= 1e-9 * std::max(1.0, std::fabs(value)))
    return "its 95 % " + what + " has zero width (" + interval_text(lower, upper) + "): no spread to judge it by";
  return "";
}

// The part of a threshold's definition before its first ':' (its reference).
std::string rule_name(const GroupThreshold& threshold) {
  return threshold.definition.substr(0, threshold.definition.find(':'));
}

struct Context {
  const StudyData& data;
  const AnalysisOptions& options;
  const AnalysisResult& result;

  std::pair<double, double> level_range(const GroupKey& group) const {
    const std::vector<double>& levels = data.levels_of(group.variant);
    if (levels.empty()) return {std::nan(""), std::nan("")};
    const auto [low, high] = std::minmax_element(levels.begin(), levels.end());
    return {*low, *high};
  }

  // The included participants (indices into data.participants) with an answered trial in the group.
  std::vector<size_t> participants_in(const GroupKey& group) const {
    std::vector<size_t> indices;
    for (size_t p = 0; p < data.participants.size(); ++p) {
      const ParticipantData& participant = data.participants[p];
      if (participant.excluded) continue;
      for (const StudyTrial& trial : participant.trials)
        if (!trial.attention_check && !trial.answers.empty() && in_group(trial.scene, trial.variant, group)) {
          indices.push_back(p);
          break;
        }
    }
    return indices;
  }

  bool adaptive(const GroupKey& group) const {
    for (const ParticipantData& participant : data.participants)
      for (const StudyTrial& trial : participant.trials)
        if (trial.track && in_group(trial.scene, trial.variant, group)) return true;
    return false;
  }

  const GroupFit* fit_of(const GroupKey& group) const {
    for (const GroupFit& fit : result.fits)
      if (fit.group == group) return &fit;
    return nullptr;
  }

  // The paper's rule of the group: for pair, the per-participant one (Polychronakis et al. 2021, 4.7).
  const GroupThreshold* paper_threshold(const GroupKey& group) const {
    const GroupThreshold* found = nullptr;
    for (const GroupThreshold& threshold : result.thresholds)
      if (threshold.group == group && (!found || (data.protocol == ProtocolKind::pair && threshold.mean)))
        found = &threshold;
    return found;
  }
};

void set_not_estimable(Headline& headline, const std::string& reason) {
  headline.status = HeadlineStatus::not_estimable;
  headline.reason = reason;
  headline.value.reset();
  headline.lower.reset();
  headline.upper.reset();
}

void add_lapse_flags(Headline& headline, const PsychometricFit& fit) {
  const double lapse = fit.model.parameters.lapse;
  if (lapse <= 1e-9) headline.flags.push_back("lapse at its bound 0 (usual for an observer who does not lapse)");
  else if (lapse >= 0.1 * (1.0 - 1e-6)) headline.flags.push_back("lapse at its upper bound 0.1");
  for (const char* side : {"slope at its lower search bound", "slope at its upper search bound"})
    if (fit.note.find(side) != std::string::npos) headline.flags.push_back(side);
}

// Constant stimuli (2afc same, pair): the first fit.
void fit_headline(const Context& context, Headline& headline) {
  const GroupFit* group_fit = context.fit_of(headline.group);
  headline.aims_at =
      "the level whose difference from the reference is seen half the time (p_see = 1/2, guess and lapse aside)";
  if (!group_fit || group_fit->fits.empty()) {
    headline.method = "psychometric fit";
    std::string why = "no psychometric fit";
    if (!group_fit) why += ": fewer than two levels tested";
    else
      for (const std::string& not_fitted : group_fit->not_fitted) why += "; " + not_fitted;
    set_not_estimable(headline, why);
    return;
  }
  const PsychometricFit& fit = group_fit->fits.front();
  headline.method = std::string(shape_name(fit.model.shape)) + " fit of every included trial (guess fixed at " +
                    number(context.result.guess_rate) + "), 95 % profile-likelihood interval";
  if (!fit.note.empty()) headline.notes.push_back("fit: " + fit.note);
  const auto [low, high] = context.level_range(headline.group);
  const std::string reason = fit_not_estimable_reason(fit, low, high);
  if (!reason.empty()) {
    set_not_estimable(headline, reason);
    return;
  }
  headline.value = fit.model.parameters.threshold;
  headline.lower = fit.threshold_interval.lower;
  headline.upper = fit.threshold_interval.upper;
  add_lapse_flags(headline, fit);
}

// Adaptive blocks: each participant's estimate is the mean of their tracks' thresholds in the group.
// `members`: the included participants with trials in the group (Context::participants_in).
void adaptive_headline(const Context& context, const std::vector<size_t>& members, Headline& headline) {
  std::set<std::string> aims;
  std::vector<double> estimates;
  int without = 0;
  for (size_t p : members) {
    std::vector<double> thresholds;
    for (const AdaptiveTrackResult& track : context.result.participants[p].tracks) {
      if (!in_group(track.block, track.variant, headline.group)) continue;
      const auto procedure =
          std::find_if(context.data.config.procedures.begin(), context.data.config.procedures.end(),
                       [&](const ProcedureConfig& config) { return config.name == track.procedure; });
      if (procedure != context.data.config.procedures.end())
        aims.insert(procedure->kind == ProcedureConfig::Kind::quest_plus
                        ? "QUEST+'s threshold parameter: the level where p_see = 1/2"
                        : "the staircase's target: the level where p_report = " +
                              format_number(staircase_target_probability(procedure->staircase), 3));
      if (track.threshold) thresholds.push_back(*track.threshold);
    }
    if (thresholds.empty()) {
      ++without;
      continue;
    }
    estimates.push_back(*mean_with_t_interval(thresholds).mean);
  }
  headline.method =
      "mean of the participants' estimates (each the mean of their tracks' thresholds by the procedure's rule), "
      "95 % Student-t interval across participants";
  for (const std::string& aim : aims) headline.aims_at += (headline.aims_at.empty() ? "" : "; ") + aim;
  headline.participants = static_cast<int>(estimates.size());
  if (without > 0)
    headline.notes.push_back(std::to_string(without) +
                             " participant(s) without a track threshold (adaptive_tracks.csv says why)");
  // The pooled fit of every adaptive trial, beside.
  if (const GroupFit* group_fit = context.fit_of(headline.group); group_fit && !group_fit->fits.empty()) {
    const PsychometricFit& fit = group_fit->fits.front();
    const auto [low, high] = context.level_range(headline.group);
    const std::string reason = fit_not_estimable_reason(fit, low, high);
    if (reason.empty()) {
      headline.pooled_fit = fit.model.parameters.threshold;
      headline.pooled_fit_lower = fit.threshold_interval.lower;
      headline.pooled_fit_upper = fit.threshold_interval.upper;
    } else {
      headline.notes.push_back("the pooled " + std::string(shape_name(fit.model.shape)) +
                               " fit is not estimable: " + reason);
    }
  }
  if (aims.size() > 1) {
    set_not_estimable(headline, "its tracks aim at different points (" + headline.aims_at +
                                    "): their mean estimates neither; adaptive_tracks.csv has each track");
    return;
  }
  const MeanInterval mean = mean_with_t_interval(estimates);
  if (estimates.size() < 2) {
    set_not_estimable(headline, estimates.empty() ? "no participant has a track threshold"
                                                  : "one participant's estimate (" + number(estimates.front()) +
                                                        "): an interval across participants needs two or more");
    return;
  }
  headline.value = mean.mean;
  headline.lower = mean.mean_lower;
  headline.upper = mean.mean_upper;
  if (const std::string reason =
          interval_failure(*mean.mean, mean.mean_lower, mean.mean_upper, "interval across participants");
      !reason.empty())
    set_not_estimable(headline, reason);
}

// Ramp: the step model over every participant's steps (ramp_model.h).
void ramp_headline(const Context& context, const std::vector<size_t>& members, Headline& headline) {
  const StudyData& data = context.data;
  std::vector<RampStep> steps;
  int index = 0;
  for (size_t p : members) {
    for (const StudyTrial& trial : data.participants[p].trials) {
      if (trial.attention_check || !in_group(trial.scene, trial.variant, headline.group)) continue;
      const std::string_view right = answers::ramp_correct_answer(trial.ramp_toward_reference);
      const std::string_view wrong = answers::ramp_correct_answer(!trial.ramp_toward_reference);
      for (size_t i = 0; i < trial.answers.size(); ++i) {
        const int step = trial.answer_steps[i];
        if (trial.answers[i].empty() || step < 1 || size_t(step) >= trial.sequence_levels.size()) continue;
        RampStep one;
        one.before = trial.sequence_levels[size_t(step - 1)];
        one.after = trial.sequence_levels[size_t(step)];
        one.answer = trial.answers[i] == right   ? RampStep::Answer::right
                     : trial.answers[i] == wrong ? RampStep::Answer::wrong
                                                 : RampStep::Answer::same;
        one.participant = index;
        steps.push_back(one);
      }
    }
    ++index;
  }
  const auto [low, high] = context.level_range(headline.group);
  const RampModelFit fit =
      fit_ramp_model(steps, data.higher_is_better, low, high, context.options.bootstrap_samples,
                     derive_seed(derive_seed(context.options.seed, headline.group.label()), "ramp"));
  headline.method =
      "step model fitted to every participant's ramp steps (maximum likelihood), 95 % percentile bootstrap "
      "interval over participants (" +
      std::to_string(fit.bootstrap_samples) + " replicates)";
  headline.aims_at =
      "the level whose difference from the reference is seen half the time (p_see = 1/2), through the step model";
  headline.participants = fit.participants;
  headline.notes.push_back("step model: slope " + number(fit.slope) + " per level unit, guess " + number(fit.guess) +
                           " (twice the wrong-way share), lapse " + number(fit.lapse) + ", " +
                           std::to_string(fit.steps) + " steps");
  if (!fit.note.empty()) headline.notes.push_back(fit.note);
  if (fit.lapse <= 1e-9) headline.flags.push_back("lapse at its bound 0 (usual for an observer who does not lapse)");
  if (!fit.converged) return set_not_estimable(headline, "the step model's fit did not converge");
  if (!(fit.threshold >= low && fit.threshold <= high))
    return set_not_estimable(headline, "the step model's threshold " + number(fit.threshold) +
                                           " lies outside the tested levels " + number(low) + " to " + number(high));
  if (fit.participants < 2)
    return set_not_estimable(headline, "one participant (step model threshold " + number(fit.threshold) +
                                           "): the interval over participants needs two or more");
  headline.value = fit.threshold;
  headline.lower = fit.lower;
  headline.upper = fit.upper;
  if (!fit.lower && context.options.bootstrap_samples == 0) headline.notes.push_back("no interval: --bootstrap 0");
  if (const std::string reason = interval_failure(fit.threshold, fit.lower, fit.upper, "bootstrap interval");
      !reason.empty())
    set_not_estimable(headline, reason);
}

// Slider: the mean of the participants' mean saved levels (the paper's rule) with its t interval.
void slider_headline(Headline& headline, const GroupThreshold* paper) {
  headline.method = "mean of the participants' mean saved levels, 95 % Student-t interval across participants";
  headline.aims_at = "the level participants accept as matching the reference (method of adjustment)";
  if (!paper || !paper->mean) return set_not_estimable(headline, "no participant saved a level");
  headline.participants = paper->participants_with_threshold;
  if (!paper->mean_lower)
    return set_not_estimable(headline, "one participant's mean saved level (" + number(*paper->mean) +
                                           "): an interval across participants needs two or more");
  headline.value = paper->mean;
  headline.lower = paper->mean_lower;
  headline.upper = paper->mean_upper;
  if (const std::string reason =
          interval_failure(*paper->mean, paper->mean_lower, paper->mean_upper, "interval across participants");
      !reason.empty())
    set_not_estimable(headline, reason);
}

// Rating: Ye et al. 2022's walk on the mean ratings, its interval from resampling participants.
void rating_headline(const Context& context, const std::vector<size_t>& members, Headline& headline,
                     const GroupThreshold* paper) {
  const StudyData& data = context.data;
  const double cutoff = context.options.rating_cutoff;
  headline.method =
      "Ye et al. 2022's rule (the most degraded level whose mean rating, and every better level's, is at least " +
      number(cutoff) + "), 95 % percentile bootstrap interval over participants";
  headline.aims_at =
      "the most degraded level of the grid whose expected mean rating stays at or above " + number(cutoff);
  // Per participant and level: the sum and count of the scores.
  std::set<double> level_set;
  std::vector<std::map<double, std::pair<double, double>>> scores;
  for (size_t p : members) {
    std::map<double, std::pair<double, double>> by_level;
    for (const StudyTrial& trial : data.participants[p].trials) {
      if (trial.attention_check || !trial.level || trial.answers.empty() ||
          !in_group(trial.scene, trial.variant, headline.group))
        continue;
      const std::string& answer = trial.answers.back();
      if (!data.rules().in_favour_of_test(answer, trial.reference_first)) continue;
      by_level[*trial.level].first += std::stod(answer);
      by_level[*trial.level].second += 1.0;
      level_set.insert(*trial.level);
    }
    scores.push_back(by_level);
  }
  headline.participants = static_cast<int>(scores.size());
  std::vector<double> best_first(level_set.begin(), level_set.end());
  if (data.higher_is_better) std::reverse(best_first.begin(), best_first.end());
  // The walk over participants weighted by `weight`: +-infinity beyond either end of the grid.
  const double beyond_best = data.higher_is_better ? kInfinity : -kInfinity;
  const auto walk = [&](const std::vector<int>& weight) {
    double threshold = beyond_best;
    for (double level : best_first) {
      double sum = 0.0, count = 0.0;
      for (size_t p = 0; p < scores.size(); ++p)
        if (const auto found = scores[p].find(level); found != scores[p].end()) {
          sum += weight[p] * found->second.first;
          count += weight[p] * found->second.second;
        }
      if (count == 0.0 || sum / count < cutoff) return threshold;
      threshold = level;
    }
    return -beyond_best;  // every level passes: at or beyond the most degraded
  };
  if (!paper || !paper->level || scores.empty())
    return set_not_estimable(headline, paper && !paper->note.empty() ? paper->note : "no level keeps the criterion");
  if (*paper->level == best_first.back())
    return set_not_estimable(headline, "every level tested keeps a mean rating of at least " + number(cutoff) +
                                           ": the threshold lies at or beyond the most degraded level tested (" +
                                           number(best_first.back()) + ")");
  headline.value = paper->level;
  if (context.options.bootstrap_samples <= 0) {
    headline.notes.push_back("no interval: --bootstrap 0");
    return;
  }
  if (scores.size() < 2)
    return set_not_estimable(headline, "one participant (Ye et al. 2022's rule gives " + number(*paper->level) +
                                           "): an interval over participants needs two or more");
  std::vector<double> replicates;
  const uint64_t seed = derive_seed(derive_seed(context.options.seed, headline.group.label()), "rating");
  for (int b = 0; b < context.options.bootstrap_samples; ++b) {
    Pcg32 random(derive_seed(seed, uint64_t(b)));
    std::vector<int> weight(scores.size(), 0);
    for (size_t i = 0; i < scores.size(); ++i) ++weight[random.below(uint32_t(scores.size()))];
    replicates.push_back(walk(weight));
  }
  std::sort(replicates.begin(), replicates.end());
  // Nearest rank on a sorted list that may hold +-infinity (nearest_rank_percentile takes finite values).
  const auto rank = [&](double percent) {
    const size_t r = std::max<size_t>(1, size_t(std::ceil(percent / 100.0 * double(replicates.size()))));
    return replicates[r - 1];
  };
  headline.lower = rank(2.5);
  headline.upper = rank(97.5);
  headline.notes.push_back("the interval's ends are levels of the grid (the rule returns one)");
  if (std::isinf(*headline.lower) || std::isinf(*headline.upper))
    set_not_estimable(headline, "its 95 % bootstrap interval " + interval_text(headline.lower, headline.upper) +
                                    " is unbounded: resampled participants put the threshold beyond the tested levels");
}

// 2afc "better": the share of trials whose answer preferred the reference, pooled over the group's conditions.
void preference_headline(const Context& context, Headline& headline) {
  uint64_t n = 0, reference_votes = 0;
  int conditions = 0;
  for (const ConditionRow& row : context.result.conditions)
    if (row.group == headline.group) {
      n += row.n;
      reference_votes += row.n - row.k;
      ++conditions;
    }
  headline.quantity = "preference share";
  headline.method =
      "share of answered trials in which the reference was chosen as better, 95 % Clopper-Pearson interval";
  headline.aims_at = "the probability that the reference is preferred (1/2: no preference either way)";
  if (n == 0) return set_not_estimable(headline, "no answered trial");
  const ProportionInterval interval = clopper_pearson_interval(reference_votes, n, 0.95);
  headline.value = double(reference_votes) / double(n);
  headline.lower = interval.lower;
  headline.upper = interval.upper;
  headline.notes.push_back(
      std::to_string(reference_votes) + " of " + std::to_string(n) + " answers preferred the reference" +
      (conditions > 1 ? " (pooled over " + std::to_string(conditions) + " conditions; conditions.csv has each)" : ""));
}

// Why the paper's rule gives another value, in one line ("" when it falls in the headline's interval).
std::string paper_difference(const Context& context, const Headline& headline, bool adaptive) {
  if (!headline.value || !headline.paper_value || !headline.lower || !headline.upper) return "";
  if (*headline.paper_value >= *headline.lower && *headline.paper_value <= *headline.upper) return "";
  const std::string value = number(*headline.paper_value);
  if (adaptive)
    return "the paper's walk gives " + value +
           ": it applies the binomial tests to the levels the procedure happened to "
           "place, not what the procedure estimates";
  switch (context.data.protocol) {
    case ProtocolKind::two_afc:
      return "the paper's walk gives " + value +
             ": the last level the binomial tests could not tell from the reference, "
             "which moves with the trials per level, while the fit estimates where p_see = 1/2";
    case ProtocolKind::pair:
      return "the paper's per-participant rule gives " + value +
             ": each participant's most degraded level still judged as good "
             "in half their trials, a level of the grid rather than the p_see = 1/2 point";
    case ProtocolKind::ramp:
      return "the paper's rule gives " + value +
             ": the most degraded step answered wrongly is the extreme of many noisy "
             "answers, so single misses between degraded stimuli pull it toward the degraded end";
    default:
      return "the paper's rule gives " + value;
  }
}

// [analysis] headline = "paper": the paper's rule in the headline, the design's estimate in a note.
void make_paper_rule_the_headline(Headline& headline, const GroupThreshold& paper) {
  std::string estimate = "the design's estimate (" + headline.method + "): ";
  if (headline.value)
    estimate += number(*headline.value) + (headline.lower ? " " + interval_text(headline.lower, headline.upper) : "");
  else estimate += std::string(headline_status_name(headline.status)) + " (" + headline.reason + ")";
  headline.notes.insert(headline.notes.begin(), estimate);
  headline.paper_rule_is_headline = true;
  headline.paper_difference.clear();
  headline.flags.clear();
  headline.method = "the paper's rule: " + paper.definition;
  headline.aims_at = "the paper's criterion";
  headline.status = HeadlineStatus::estimated;
  headline.reason.clear();
  headline.value = paper.level;
  headline.lower = paper.mean_lower;
  headline.upper = paper.mean_upper;
  if (!paper.level) set_not_estimable(headline, paper.note.empty() ? "the rule finds no level" : paper.note);
}

}  // namespace

std::string fit_not_estimable_reason(const PsychometricFit& fit, double low, double high) {
  const std::string shape(shape_name(fit.model.shape));
  const double threshold = fit.model.parameters.threshold;
  if (!fit.converged) return "the " + shape + " fit did not converge";
  if (!std::isfinite(threshold) || !(threshold >= low && threshold <= high))
    return "the " + shape + " fit's threshold " + number(threshold) + " lies outside the tested levels " + number(low) +
           " to " + number(high);
  const std::string interval = interval_failure(threshold, fit.threshold_interval.lower, fit.threshold_interval.upper,
                                                "profile-likelihood interval");
  if (!interval.empty()) return interval;
  if (!std::isnan(fit.bootstrap_threshold_interval.lower) &&
      fit.bootstrap_threshold_interval.upper - fit.bootstrap_threshold_interval.lower <=
          1e-9 * std::max(1.0, std::fabs(threshold)))
    return "its bootstrap interval has zero width (" +
           format_interval(fit.bootstrap_threshold_interval.lower, fit.bootstrap_threshold_interval.upper, 4) +
           "): the replicates' fits all land on one value";
  return "";
}

std::vector<Headline> study_headlines(const StudyData& data, const AnalysisOptions& options,
                                      const AnalysisResult& result) {
  const Context context{data, options, result};
  std::set<GroupKey> groups;
  for (const ConditionRow& row : result.conditions) groups.insert(row.group);
  for (const GroupThreshold& threshold : result.thresholds) groups.insert(threshold.group);
  const bool better = data.protocol == ProtocolKind::two_afc && data.question == TwoAfcQuestion::better;
  std::vector<Headline> headlines;
  for (const GroupKey& group : groups) {
    Headline headline;
    headline.group = group;
    headline.quantity = "threshold";
    const std::vector<size_t> members = context.participants_in(group);
    headline.participants = static_cast<int>(members.size());
    const GroupThreshold* paper = context.paper_threshold(group);
    if (paper) {
      headline.paper_rule = rule_name(*paper);
      headline.paper_value = paper->level;
    }
    const bool adaptive = context.adaptive(group);
    if (better) {
      headline.paper_rule = "Ye et al. 2022, Table 2 (a one-sided binomial test per condition: the preference table)";
      headline.paper_value.reset();
      preference_headline(context, headline);
    } else if (data.levels.empty()) {
      set_not_estimable(headline, "the study has no levels: no level axis for a threshold");
    } else if (adaptive) {
      adaptive_headline(context, members, headline);
    } else if (data.protocol == ProtocolKind::ramp) {
      ramp_headline(context, members, headline);
    } else if (data.protocol == ProtocolKind::slider) {
      slider_headline(headline, paper);
    } else if (data.protocol == ProtocolKind::rating) {
      rating_headline(context, members, headline, paper);
    } else {
      fit_headline(context, headline);
    }
    headline.paper_difference = paper_difference(context, headline, adaptive);
    if (data.config.analysis.headline_is_paper_rule && paper && !better) make_paper_rule_the_headline(headline, *paper);
    headlines.push_back(std::move(headline));
  }
  return headlines;
}

}  // namespace fovlab::analysis
