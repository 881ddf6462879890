#pragma once
// QUEST+ (Watson 2017) on a study's level grid: a Bayesian adaptive procedure over the parameters of
// a psychometric function (study/psychometric/psychometric_function.h: threshold, slope, lapse; the
// guess rate fixed by the protocol). Each trial presents the level whose answer is expected to leave
// the least posterior entropy; each answer (difference seen or not) multiplies the posterior by its
// likelihood. Like the staircases, it is a pure function of its rule and the answers so far: a
// session resumed or replayed from its log folds the logged answers in again and gets the same
// levels. A tie between levels (equal expected entropy) goes to the first in grid order, as in
// Watson's reference code; nothing is drawn at random.
//
// The expected entropy of presenting level x, with posterior w over the parameter grid and
// L1 = p_report(x; params), L0 = 1 - L1:
//   A_r = sum_p w_p L_r,p            (the probability of answer r)
//   B_r = sum_p w_p L_r,p log(w_p L_r,p)
//   E[H] = sum_r A_r H_r = sum_r (A_r log A_r - B_r)     (nats)
// computed from tabulated log L and log w: no logarithm inside the loop over the grid.
#include <optional>
#include <string>
#include <vector>

#include "study/psychometric/psychometric_function.h"

namespace fovlab {

struct QuestPlusRule {
  PsychometricShape shape = PsychometricShape::logistic;
  bool rising = true;              // p_see grows with the level value
  double guess = 0.0;              // p_report where nothing is seen (the protocol's chance rate)
  std::vector<double> thresholds;  // the parameter grid, each ascending
  std::vector<double> slopes;
  std::vector<double> lapses;
  // The prior over thresholds: uniform, or (prior_sd > 0) a normal of this mean and SD; uniform
  // over slopes and lapses.
  double prior_mean = 0.0;
  double prior_sd = 0.0;
  int max_trials = 40;
  double stop_entropy_bits = 0.0;  // stops once the posterior's entropy is at most this (0: never)
  double stop_interval_width =
      0.0;  // stops once the threshold's 95 % credible interval is at most this wide (0: never)
  bool operator==(const QuestPlusRule&) const = default;
};

// Limits on the grids (the largest QUEST+ docs/config.md allows; `fovlab bench-quest` times a
// choice at these sizes).
constexpr size_t kQuestPlusMaxLevels = 100;
constexpr size_t kQuestPlusMaxParameters = 20000;  // thresholds x slopes x lapses
// A session's QUEST+ tables in all (levels x grid points, summed over the distinct (rule, levels)
// of its tracks: 3 doubles an entry, 96 MB at this limit).
constexpr size_t kQuestPlusMaxTableEntries = 4000000;
// How far the threshold grid may reach past the levels, in spans of the levels (highest - lowest) on
// each side: no trial tells thresholds apart that far from every level (p_see is flat there), and
// the grid's span and its differences from the levels stay finite (a grid of +-1e308 overflowed).
constexpr double kQuestPlusThresholdReach = 10.0;

// Default grids for a level grid (any order): 41 thresholds evenly over the levels' range (Weibull:
// log-spaced, levels > 0), 8 slopes log-spaced over transitions (10 % to 90 % of p_see) from the
// whole range to a 20th of it (Weibull: 1 to 10), lapses 0, 0.02, 0.04.
std::vector<double> default_quest_thresholds(const std::vector<double>& levels, PsychometricShape shape);
std::vector<double> default_quest_slopes(const std::vector<double>& levels, PsychometricShape shape);
std::vector<double> default_quest_lapses();

// What is wrong with a rule on a level grid, as "KEY: expected ..." (a config error), or nullopt:
// empty or unsorted grids, grids past the limits, thresholds past kQuestPlusThresholdReach, a guess
// and lapse that leave no room for p_see, Weibull thresholds <= 0, a prior with no mass on the
// threshold grid, stopping rules that can never be met.
std::optional<std::string> quest_plus_rule_error(const QuestPlusRule& rule, const std::vector<double>& levels);

struct QuestPlusState {
  std::vector<double> posterior;  // over (threshold, slope, lapse), threshold-major; sums to 1
  int index = 0;                  // level grid index of the next trial
  int trials = 0;
  bool finished = false;
};

struct QuestPlusEstimate {
  double threshold_mean = 0.0;   // posterior mean
  double threshold_lower = 0.0;  // 95 % equal-tailed credible interval on the threshold grid
  double threshold_upper = 0.0;
  double slope_mean = 0.0;
  double lapse_mean = 0.0;
  double entropy_bits = 0.0;  // of the whole posterior
};

// A rule tabulated on a level grid: p_report of every (level, parameters) pair.
class QuestPlus {
 public:
  QuestPlus(QuestPlusRule rule, std::vector<double> levels);  // the rule must be valid (quest_plus_rule_error)

  QuestPlusState start() const;
  // The state after one more answer at the state's level.
  QuestPlusState next(QuestPlusState state, bool seen) const;
  QuestPlusState replay(const std::vector<bool>& answers) const;
  // E[H] of each level (nats), and the level that minimises it.
  std::vector<double> expected_entropies(const std::vector<double>& posterior) const;
  int choose(const std::vector<double>& posterior) const;
  QuestPlusEstimate estimate(const std::vector<double>& posterior) const;

  const QuestPlusRule& rule() const { return rule_; }
  size_t parameter_count() const { return parameters_; }

 private:
  QuestPlusRule rule_;
  std::vector<double> levels_;
  size_t parameters_ = 0;
  std::vector<double> seen_, log_seen_, log_not_seen_;  // [level][parameter]
};

}  // namespace fovlab
