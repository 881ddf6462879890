#include "analysis/study/study_analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "analysis/statistics/mean_interval.h"
#include "analysis/statistics/multiple_comparisons.h"
#include "analysis/study/headline.h"
#include "analysis/study/preference_table.h"
#include "analysis/study/rating_grid.h"
#include "analysis/study/adaptive_tracks.h"
#include "core/number_text.h"
#include "core/prng.h"

namespace fovlab::analysis {
namespace {

// Groups a trial counts in: its scene, and "all" scenes pooled when the study has several.
std::vector<GroupKey> groups_of(const StudyTrial& trial, bool pool_scenes) {
  std::vector<GroupKey> groups = {{trial.scene, trial.variant}};
  if (pool_scenes) groups.push_back({"all", trial.variant});
  return groups;
}

// Levels from the one most like the reference to the most degraded.
std::vector<double> best_first(std::vector<double> levels, bool higher_is_better) {
  std::sort(levels.begin(), levels.end());
  if (higher_is_better) std::reverse(levels.begin(), levels.end());
  return levels;
}

bool more_degraded_than(double a, double b, bool higher_is_better) { return higher_is_better ? a < b : a > b; }

// The more degraded of two levels of a ramp step (none: the reference, better than every level).
std::optional<double> more_degraded(std::optional<double> a, std::optional<double> b, bool higher_is_better) {
  if (!a) return b;
  if (!b) return a;
  return more_degraded_than(*a, *b, higher_is_better) ? a : b;
}

struct ConditionCounts {
  std::optional<double> level;
  std::set<std::string> methods;
  uint64_t n = 0;
  uint64_t k = 0;
  double rating_sum = 0.0;
  double rating_square_sum = 0.0;
};

// ---------------------------------------------------------------------------------------------
// Comparison protocols: counts per condition, tests, study-level thresholds and fits.

class ComparisonAnalysis {
 public:
  ComparisonAnalysis(const StudyData& data, const AnalysisOptions& options, AnalysisResult& result)
      : data_(data), options_(options), result_(result) {}

  void run(const std::vector<const ParticipantData*>& included, bool pool_scenes) {
    count(included, pool_scenes);
    for (const auto& [group, conditions] : counts_) {
      add_rows(group, conditions);  // the threshold and the fits read the group's rows
      add_threshold(group);
      add_fits(group);
      compare_threshold_with_fit(group);
    }
  }

 private:
  void count(const std::vector<const ParticipantData*>& included, bool pool_scenes) {
    int unanswered = 0;
    for (const ParticipantData* participant : included)
      for (const StudyTrial& trial : participant->trials) {
        if (trial.attention_check || trial.answers.empty()) continue;
        const std::string& answer = trial.answers.back();
        const std::optional<bool> favour = data_.rules().in_favour_of_test(answer, trial.reference_first);
        if (!favour) {
          ++unanswered;
          continue;
        }
        for (const GroupKey& group : groups_of(trial, pool_scenes)) {
          ConditionCounts& counts = counts_[group][trial.condition];
          counts.level = trial.level;
          counts.methods.insert(trial.method);
          ++counts.n;
          counts.k += *favour ? 1 : 0;
          if (data_.protocol == ProtocolKind::rating) {
            const double score = std::stod(answer);
            counts.rating_sum += score;
            counts.rating_square_sum += score * score;
          }
        }
      }
    if (unanswered > 0)
      result_.left_out.push_back(
          {std::to_string(unanswered) + " trial(s)", "no answer of this protocol (a timeout): not counted"});
    if (counts_.empty() && !included.empty())
      result_.left_out.push_back(
          {"study " + data_.study, "no answered comparison trial of an included participant: no condition to test"});
    // Levels of the config no included trial tested (a conditions file's variant: of its own levels).
    // An adaptive block chooses its levels, so a level none of its tracks reached is no gap in the
    // data: not listed when the study has adaptive blocks.
    const bool adaptive = std::any_of(data_.config.blocks.begin(), data_.config.blocks.end(),
                                      [](const BlockConfig& block) { return block.procedure >= 0; });
    for (const auto& [group, conditions] : counts_) {
      if (adaptive) break;
      std::set<double> tested;
      for (const auto& [name, counts] : conditions)
        if (counts.level) tested.insert(*counts.level);
      for (double level : data_.levels_of(group.variant))
        if (!tested.count(level))
          result_.left_out.push_back(
              {"condition " + data_.level_parameter + "=" + format_number(level, 6) + " in " + group.label(),
               "no trial of an included participant: nothing to analyse"});
    }
  }

  void add_rows(const GroupKey& group, const std::map<std::string, ConditionCounts>& conditions) {
    std::vector<ConditionRow> rows;
    for (const auto& [name, counts] : conditions) {
      ConditionRow row;
      row.group = group;
      row.condition = name;
      row.level = counts.level;
      for (const std::string& method : counts.methods) row.method += (row.method.empty() ? "" : "+") + method;
      row.n = counts.n;
      row.k = counts.k;
      row.proportion = double(counts.k) / double(counts.n);
      row.p_value = binomial_test_p_value(counts.k, counts.n, 0.5, options_.alternative);
      row.log10_p = binomial_test_log10_p_value(counts.k, counts.n, 0.5, options_.alternative);
      row.interval = clopper_pearson_interval(counts.k, counts.n, 0.95);
      if (data_.protocol == ProtocolKind::rating) {
        const double n = double(counts.n);
        const double mean = counts.rating_sum / n;
        row.mean_rating = mean;
        if (counts.n >= 2)
          row.sd_rating = std::sqrt(std::max(0.0, (counts.rating_square_sum - n * mean * mean) / (n - 1.0)));
      }
      rows.push_back(row);
    }
    std::sort(rows.begin(), rows.end(), [](const ConditionRow& a, const ConditionRow& b) {
      if (a.level != b.level) return a.level < b.level;  // none first
      return a.condition < b.condition;
    });
    std::vector<double> p_values;
    for (const ConditionRow& row : rows) p_values.push_back(row.p_value);
    const std::vector<double> adjusted = holm_adjusted(p_values);
    for (size_t i = 0; i < rows.size(); ++i) {
      rows[i].p_holm = adjusted[i];
      rows[i].stars = significance_stars(rows[i].p_holm);  // the p the threshold uses
    }
    result_.conditions.insert(result_.conditions.end(), rows.begin(), rows.end());
  }

  std::vector<const ConditionRow*> rows_of(const GroupKey& group) const {
    std::vector<const ConditionRow*> rows;
    for (const ConditionRow& row : result_.conditions)
      if (row.group == group && row.level) rows.push_back(&row);
    return rows;
  }

  // From the best level down: the most degraded level such that it and every better level pass.
  template <typename Passes>
  std::optional<double> walk_from_best(const GroupKey& group, Passes passes, std::string& note) const {
    std::map<double, const ConditionRow*> by_level;
    for (const ConditionRow* row : rows_of(group)) by_level[*row->level] = row;
    std::vector<double> levels;
    for (const auto& [level, row] : by_level) levels.push_back(level);
    std::optional<double> threshold;
    for (double level : best_first(levels, data_.higher_is_better)) {
      if (!passes(*by_level[level])) {
        if (!threshold) note = "even the best level tested (" + format_number(level, 6) + ") fails the criterion";
        return threshold;
      }
      threshold = level;
    }
    if (threshold) note = "every level tested passes: the threshold is at or below the most degraded level";
    return threshold;
  }

  void add_threshold(const GroupKey& group) {
    if (rows_of(group).empty()) return;
    GroupThreshold threshold;
    threshold.group = group;
    if (data_.protocol == ProtocolKind::rating) {
      threshold.definition =
          "Ye et al. 2022, 4.4.2: the most degraded level whose mean rating, and that of every better level, "
          "is at least " +
          format_number(options_.rating_cutoff, 6);
      threshold.level = walk_from_best(
          group, [&](const ConditionRow& row) { return row.mean_rating && *row.mean_rating >= options_.rating_cutoff; },
          threshold.note);
    } else {
      const std::string judged(data_.rules().judged_words);
      threshold.definition =
          std::string(data_.rules().threshold_definition) +
          ": the most degraded level from which on no level is distinguished from the reference; a level is "
          "distinguished when the test is " +
          judged + " in less than half of its trials and the Holm-adjusted exact binomial p (H0: 1/2, " +
          alternative_name(options_.alternative) + ") is below " + format_number(options_.alpha, 6);
      // Can any outcome distinguish a level? Holm's smallest adjusted p is m times the smallest raw p,
      // so with m levels the most extreme answers (none in favour) must reach p < alpha / m somewhere.
      const std::vector<const ConditionRow*> rows = rows_of(group);
      double smallest_possible_p = 1.0;
      uint64_t most_trials = 0;
      for (const ConditionRow* row : rows) {
        smallest_possible_p =
            std::min(smallest_possible_p, binomial_test_p_value(0, row->n, 0.5, options_.alternative));
        most_trials = std::max(most_trials, row->n);
      }
      const double smallest_possible_holm = std::min(1.0, double(rows.size()) * smallest_possible_p);
      if (options_.alternative == Alternative::greater) {
        threshold.note =
            "with --alternative greater the tests ask whether the test is favoured, so no level can count "
            "as distinguished: no threshold";
        threshold.unsupported = true;
      } else if (smallest_possible_holm >= options_.alpha) {
        threshold.note = "too few trials: with " + std::to_string(rows.size()) + " levels and at most " +
                         std::to_string(most_trials) +
                         " trials a level, even answers all against the test give a "
                         "Holm-adjusted p of at least " +
                         format_number(smallest_possible_holm, 3) + " >= alpha " + format_number(options_.alpha, 3) +
                         ", so no level could be distinguished: no threshold";
        threshold.unsupported = true;
      } else {
        threshold.level = walk_from_best(
            group, [&](const ConditionRow& row) { return !(row.proportion < 0.5 && row.p_holm < options_.alpha); },
            threshold.note);
        // Levels that pass only because Holm's correction lifted their p over alpha, at or above the threshold.
        if (threshold.level)
          for (const ConditionRow* row : rows)
            if (row->proportion < 0.5 && row->p_value < options_.alpha && row->p_holm >= options_.alpha &&
                !more_degraded_than(*row->level, *threshold.level, data_.higher_is_better))
              append_note(threshold.note,
                          "level " + format_number(*row->level, 6) + " passes only after Holm's correction (" +
                              std::to_string(row->k) + " of " + std::to_string(row->n) + " " + judged + ", p " +
                              format_number(row->p_value, 3) + ", Holm " + format_number(row->p_holm, 3) + ")");
      }
    }
    result_.thresholds.push_back(threshold);
  }

  void add_fits(const GroupKey& group) {
    GroupFit group_fit;
    group_fit.group = group;
    for (const ConditionRow* row : rows_of(group)) group_fit.data.push_back({*row->level, row->n, row->n - row->k});
    std::set<double> distinct;
    for (const LevelCounts& counts : group_fit.data) distinct.insert(counts.level);
    if (distinct.size() < 2) return;
    const bool positive = *distinct.begin() > 0.0;
    for (PsychometricShape shape : options_.shapes) {
      if (shape == PsychometricShape::weibull && !positive) {
        group_fit.not_fitted.push_back(std::string(shape_name(shape)) + ": needs levels > 0");
        continue;
      }
      FitOptions fit_options;
      fit_options.shape = shape;
      fit_options.rising = !data_.higher_is_better;
      fit_options.guess = result_.guess_rate;
      fit_options.bootstrap_samples = options_.bootstrap_samples;
      fit_options.seed = derive_seed(derive_seed(options_.seed, group.label()), shape_name(shape));
      try {
        group_fit.fits.push_back(fit_psychometric(group_fit.data, fit_options));
      } catch (const std::invalid_argument& error) {
        group_fit.not_fitted.push_back(std::string(shape_name(shape)) + ": " + error.what());
      }
    }
    result_.fits.push_back(group_fit);
  }

  // The walk's threshold is the last level the tests could not tell from the reference, so it
  // depends on the trials per level; the fit's threshold is where the answers cross half-way, which
  // the walk places between its level and the next more degraded one (the first distinguished).
  // When the first fit's interval lies wholly outside that bracket, the note says so, both figures
  // given. (A grid step wider than the interval alone does not trigger it.)
  void compare_threshold_with_fit(const GroupKey& group) {
    if (result_.thresholds.empty() || result_.fits.empty() || data_.protocol == ProtocolKind::rating) return;
    GroupThreshold& threshold = result_.thresholds.back();
    const GroupFit& group_fit = result_.fits.back();
    if (!(threshold.group == group) || !(group_fit.group == group) || !threshold.level || group_fit.fits.empty())
      return;
    const PsychometricFit& fit = group_fit.fits.front();
    const ParameterInterval& interval = fit.threshold_interval;
    const double walk = *threshold.level;
    const bool higher_is_better = data_.higher_is_better;
    double degraded_end =
        higher_is_better ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    for (const ConditionRow* row : rows_of(group))
      if (more_degraded_than(*row->level, walk, higher_is_better) &&
          !more_degraded_than(*row->level, degraded_end, higher_is_better))
        degraded_end = *row->level;  // the next more degraded level tested
    const double low = std::min(walk, degraded_end), high = std::max(walk, degraded_end);
    if (!(interval.upper < low || interval.lower > high)) return;
    const bool beyond_the_walk = higher_is_better ? interval.upper < low : interval.lower > high;
    append_note(
        threshold.note,
        "the " + std::string(shape_name(fit.model.shape)) + " fit's threshold is " +
            format_number(fit.model.parameters.threshold, 4) + " " +
            format_interval(interval.lower, interval.upper, 4) + ", outside the walk's bracket (" +
            format_number(walk, 6) +
            (std::isinf(degraded_end) ? " or more degraded" : " to the next more degraded level") + "): " +
            (beyond_the_walk
                 ? "more degraded than the walk says (levels the tests passed were seen more than half the time)"
                 : "less degraded than the walk says: the tests could not tell the levels between apart "
                   "with these trials"));
  }

  const StudyData& data_;
  const AnalysisOptions& options_;
  AnalysisResult& result_;
  std::map<GroupKey, std::map<std::string, ConditionCounts>> counts_;
};

// The guess rate the fits hold fixed (docs/analysis.md, "Psychometric fits").
void choose_guess_rate(const StudyData& data, const AnalysisOptions& options,
                       const std::vector<const ParticipantData*>& included, AnalysisResult& result) {
  if (options.guess_rate) {
    result.guess_rate = *options.guess_rate;
    result.guess_rate_source = "--guess-rate";
    return;
  }
  const ProtocolRules& rules = data.rules();
  if (rules.kind == ProtocolKind::two_afc && rules.identical.empty()) {
    result.guess_rate = 0.5;
    result.guess_rate_source = "2afc forced choice: chance is 1/2";
    return;
  }
  // Attention checks show identical stimuli: any answer but "identical" is a false alarm.
  const std::string_view identical = rules.identical;
  uint64_t checks = 0, false_alarms = 0;
  for (const ParticipantData* participant : included)
    for (const StudyTrial& trial : participant->trials)
      if (trial.attention_check && !trial.answers.empty() && !trial.answers.back().empty()) {
        ++checks;
        false_alarms += trial.answers.back() == identical ? 0 : 1;
      }
  if (checks == 0) {
    result.guess_rate = 0.0;
    result.guess_rate_source = "no attention checks: 0";
    return;
  }
  const double false_alarm_rate = double(false_alarms) / double(checks);
  // Pair: a false alarm picks either interval, so half of them name the reference.
  result.guess_rate = rules.guess_rate_scale * false_alarm_rate;
  result.guess_rate_source = "attention checks of included participants: " + std::to_string(false_alarms) + " of " +
                             std::to_string(checks) + " not judged identical" +
                             (rules.guess_rate_scale != 1.0 ? " (halved: either interval)" : "");
}

// ---------------------------------------------------------------------------------------------
// Per-participant thresholds: pair, ramp, slider (Polychronakis et al. 2021, 4.7).

// Pair: the most degraded level such that it and every better level were judged as good as or
// better than the reference in at least half of the participant's trials.
std::optional<double> pair_threshold(const StudyData& data, const std::vector<const StudyTrial*>& trials,
                                     std::string& note) {
  std::map<double, std::pair<int, int>> counts;  // level -> (in favour, n)
  for (const StudyTrial* trial : trials) {
    const std::optional<bool> favour = data.rules().in_favour_of_test(trial->answers.back(), trial->reference_first);
    if (!favour || !trial->level) continue;
    auto& [k, n] = counts[*trial->level];
    k += *favour ? 1 : 0;
    ++n;
  }
  std::vector<double> levels;
  for (const auto& [level, kn] : counts) levels.push_back(level);
  std::optional<double> threshold;
  for (double level : best_first(levels, data.higher_is_better)) {
    const auto [k, n] = counts[level];
    if (2 * k < n) break;
    threshold = level;
  }
  if (!threshold && !levels.empty()) note = "the reference was preferred even at the best level";
  return threshold;
}

// Ramp, one trial: the most degraded level of the steps answered wrongly (a change missed, or seen
// the wrong way); every step right: the best level (censored there). A ramp with a step left
// unanswered (a timeout) has no threshold: what the missing answer would have said is unknown.
enum class RampOutcome { wrong_step, all_right, unanswered_step };

RampOutcome ramp_trial_threshold(const StudyData& data, const StudyTrial& trial, std::optional<double>& threshold) {
  const std::string_view correct = answers::ramp_correct_answer(trial.ramp_toward_reference);
  const size_t steps = trial.sequence_levels.empty() ? 0 : trial.sequence_levels.size() - 1;
  std::vector<bool> answered(steps + 1, false);
  threshold.reset();
  for (size_t i = 0; i < trial.answers.size(); ++i) {
    const int step = trial.answer_steps[i];
    if (trial.answers[i].empty() || step < 1 || step > static_cast<int>(steps)) continue;
    answered[size_t(step)] = true;
    if (trial.answers[i] == correct) continue;
    const std::optional<double> level = more_degraded(trial.sequence_levels[size_t(step - 1)],
                                                      trial.sequence_levels[size_t(step)], data.higher_is_better);
    threshold = more_degraded(threshold, level, data.higher_is_better);
  }
  if (steps == 0 || std::count(answered.begin() + 1, answered.end(), true) < static_cast<long>(steps)) {
    threshold.reset();
    return RampOutcome::unanswered_step;
  }
  if (threshold) return RampOutcome::wrong_step;
  for (const std::optional<double>& level : trial.sequence_levels)  // the best level of the ramp
    if (level && (!threshold || (data.higher_is_better ? *level > *threshold : *level < *threshold))) threshold = level;
  return RampOutcome::all_right;
}

void add_participant_thresholds(const StudyData& data, bool pool_scenes, AnalysisResult& result) {
  std::map<GroupKey, std::vector<double>> per_group;
  std::map<GroupKey, int> without;
  for (size_t p = 0; p < data.participants.size(); ++p) {  // result.participants is in the same order
    const ParticipantData& participant = data.participants[p];
    ParticipantRow& row = result.participants[p];
    if (participant.excluded) continue;
    std::map<GroupKey, std::vector<const StudyTrial*>> trials;
    for (const StudyTrial& trial : participant.trials)
      if (!trial.attention_check && !trial.answers.empty())
        for (const GroupKey& group : groups_of(trial, pool_scenes)) trials[group].push_back(&trial);
    for (const auto& [group, group_trials] : trials) {
      ParticipantThreshold threshold;
      threshold.group = group;
      if (data.protocol == ProtocolKind::pair) {
        threshold.level = pair_threshold(data, group_trials, threshold.note);
      } else if (data.protocol == ProtocolKind::ramp) {
        std::vector<double> levels;
        int censored_count = 0, unanswered_count = 0;
        for (const StudyTrial* trial : group_trials) {
          std::optional<double> level;
          const RampOutcome outcome = ramp_trial_threshold(data, *trial, level);
          if (level) levels.push_back(*level);
          censored_count += outcome == RampOutcome::all_right ? 1 : 0;
          unanswered_count += outcome == RampOutcome::unanswered_step ? 1 : 0;
        }
        threshold.level = mean_with_t_interval(levels).mean;
        const std::string of_ramps = " of " + std::to_string(group_trials.size()) + " ramps ";
        if (censored_count > 0)
          threshold.note =
              std::to_string(censored_count) + of_ramps + "had every step right: counted at the best level";
        if (unanswered_count > 0)
          threshold.note += std::string(threshold.note.empty() ? "" : "; ") + std::to_string(unanswered_count) +
                            of_ramps + "had a step left unanswered: not counted";
      } else if (data.protocol == ProtocolKind::slider) {
        std::vector<double> levels;
        for (const StudyTrial* trial : group_trials)
          if (trial->saved_level) levels.push_back(*trial->saved_level);
        threshold.level = mean_with_t_interval(levels).mean;
        if (levels.size() < group_trials.size())
          threshold.note =
              std::to_string(group_trials.size() - levels.size()) + " slider trial(s) without a saved level";
      }
      if (threshold.level) per_group[group].push_back(*threshold.level);
      else ++without[group];
      row.thresholds.push_back(threshold);
    }
  }
  const char* definition =
      data.protocol == ProtocolKind::pair
          ? "Polychronakis et al. 2021, 4.7: per participant, the most degraded level such that it and every better "
            "level were judged "
            "as good as or better than the reference in at least half of the trials; mean and SD across participants"
      : data.protocol == ProtocolKind::ramp
          ? "Polychronakis et al. 2021, 4.7: per ramp, the most degraded level of a step answered wrongly (a change "
            "missed or seen the wrong "
            "way; every step right: the best level); per participant the mean over ramps; mean and SD across "
            "participants"
          : "Polychronakis et al. 2021, 4.7: per participant, the mean saved level; mean and SD across participants";
  std::set<GroupKey> groups;
  for (const auto& [group, values] : per_group) groups.insert(group);
  for (const auto& [group, count] : without) groups.insert(group);
  for (const GroupKey& group : groups) {
    const MeanInterval summary = mean_with_t_interval(per_group[group]);
    GroupThreshold threshold;
    threshold.group = group;
    threshold.definition = definition;
    threshold.mean = summary.mean;
    threshold.sd = summary.sd;
    threshold.mean_lower = summary.mean_lower;
    threshold.mean_upper = summary.mean_upper;
    threshold.level = summary.mean;
    threshold.participants_with_threshold = summary.count;
    threshold.participants_without_threshold = without[group];
    if (!summary.mean) threshold.note = "no participant reached a threshold";
    result.thresholds.push_back(threshold);
  }
}

}  // namespace

AnalysisResult analyse_study(const StudyData& data, const AnalysisOptions& options) {
  AnalysisResult result;
  result.study = data.study;
  result.protocol = data.protocol;
  result.question = data.question;
  result.level_parameter = data.level_parameter;
  result.higher_is_better = data.higher_is_better;
  result.levels = data.levels;
  result.alternative = options.alternative;
  result.alpha = options.alpha;
  result.rating_cutoff = options.rating_cutoff;
  result.inputs = data.inputs;
  result.observers = data.observers;
  result.left_out = data.left_out;
  result.config_versions = data.config_versions;

  std::vector<const ParticipantData*> included;
  std::set<std::string> scenes;
  for (const ParticipantData& participant : data.participants) {
    ParticipantRow row;
    row.participant = participant.participant;
    row.log_path = participant.log_path;
    row.observer = participant.observer;
    row.complete_trials = static_cast<int>(participant.trials.size());
    row.attention_checks = participant.attention_checks;
    row.attention_errors = participant.attention_errors;
    row.excluded = participant.excluded;
    row.session_ended = participant.session_ended;
    row.log_status = participant.log_status;
    row.log_note = participant.log_note;
    row.latency_recorded = participant.latency_recorded;
    row.latency = participant.latency;
    row.dropped_frames = participant.dropped_frames;
    row.frame_intervals = participant.frame_intervals;
    row.gaze_source = participant.gaze_source;
    row.present_clock = participant.present_clock;
    row.headset = participant.headset;
    row.validation = participant.validation;
    row.practice_trials = participant.practice_trials;
    row.tracks = adaptive_tracks(data, participant);
    result.participants.push_back(row);
    if (participant.excluded) {
      result.left_out.push_back({"participant " + participant.participant,
                                 "excluded by attention checks (" + std::to_string(participant.attention_errors) +
                                     (participant.attention_errors == 1 ? " error" : " errors") +
                                     "): no trial counted"});
      continue;
    }
    included.push_back(&participant);
    for (const StudyTrial& trial : participant.trials) scenes.insert(trial.scene);
  }
  const bool pool_scenes = scenes.size() > 1;
  if (data.levels.empty())
    result.left_out.push_back({"thresholds and fits",
                               "the study has no levels: its conditions are tested, but there is "
                               "no level axis for a threshold or a fit"});
  choose_guess_rate(data, options, included, result);
  if (data.rules().judges_against_reference) ComparisonAnalysis(data, options, result).run(included, pool_scenes);
  // Ye et al. 2022: the pilot's grid of two test parameters (rating), and Table 2's layout (2afc "better").
  result.rating_grid = rating_grid(data);
  result.preferences = preference_table(preference_counts(result, std::string(describe(data.reference_method).name)));
  if (data.protocol == ProtocolKind::pair || data.protocol == ProtocolKind::ramp ||
      data.protocol == ProtocolKind::slider)
    add_participant_thresholds(data, pool_scenes, result);
  if (included.empty()) result.left_out.push_back({"study " + data.study, "every participant was excluded: no result"});
  result.headlines = study_headlines(data, options, result);
  std::vector<const FrameIntervalSummary*> sessions;
  for (const ParticipantRow& participant : result.participants)
    if (!participant.excluded) sessions.push_back(&participant.frame_intervals);
  result.frame_intervals = pool_frame_intervals(sessions);
  return result;
}

}  // namespace fovlab::analysis
