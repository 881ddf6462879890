// Tests of study/schedule/staircase.h: a hand-worked track, the grid's ends, replay from answers,
// the rule's bad values, and convergence to the probabilities Levitt (1971) and Kaernbach (1991)
// derive, with a simulated observer.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/prng.h"
#include "study/schedule/staircase.h"

namespace fovlab {
namespace {

TEST(Staircase, OneUpTwoDownFollowsTheHandWorkedTrack) {
  // Grid of 10, start 0, steps 2 then 1 after the first reversal.
  StaircaseRule rule;
  rule.down = 2;
  rule.step_sizes = {2, 1};
  rule.max_trials = 20;
  const std::vector<bool> answers = {true, true, true, true, false, true, true, false, false};
  std::vector<int> track;
  StaircaseState state = start_staircase(rule);
  for (const bool correct : answers) {
    track.push_back(state.index);
    state = next_staircase_state(rule, state, correct, 10);
  }
  // 0,0 -> 2; 2,2 -> 4; 4 wrong -> 2 (reversal at 4; steps of 1 now); 2,2 -> 3 (reversal at 2);
  // 3 wrong -> 2 (reversal at 3); 2 wrong -> 1.
  EXPECT_EQ(track, (std::vector<int>{0, 0, 2, 2, 4, 2, 2, 3, 2}));
  EXPECT_EQ(state.index, 1);
  EXPECT_EQ(state.reversal_indices, (std::vector<int>{4, 2, 3}));
  EXPECT_EQ(state.trials, 9);
  EXPECT_FALSE(state.finished);
  // The same state from the answers alone (resume and replay).
  const StaircaseState again = replay_staircase(rule, answers, 10);
  EXPECT_EQ(again.index, state.index);
  EXPECT_EQ(again.reversal_indices, state.reversal_indices);
  // Threshold: the mean level of the last reversals (levels 10, 20, ..., 100 on the grid).
  const std::vector<double> levels = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100};
  rule.reversals_averaged = 2;
  EXPECT_DOUBLE_EQ(staircase_threshold(rule, state, levels).value_or(0), (30.0 + 40.0) / 2.0);
  rule.reversals_averaged = 4;
  EXPECT_FALSE(staircase_threshold(rule, state, levels));
}

TEST(Staircase, MovesStopAtTheGridsEndsAndAStopIsFinal) {
  StaircaseRule rule;
  rule.kind = StaircaseRule::Kind::weighted;
  rule.harder_steps = 1;
  rule.easier_steps = 3;
  rule.start_index = 1;
  rule.max_trials = 4;
  StaircaseState state = start_staircase(rule);
  state = next_staircase_state(rule, state, false, 5);  // 1 - 3: held at 0
  EXPECT_EQ(state.index, 0);
  state = next_staircase_state(rule, state, true, 5);  // reversal at 0
  EXPECT_EQ(state.index, 1);
  EXPECT_EQ(state.reversal_indices, (std::vector<int>{0}));
  state = next_staircase_state(rule, state, true, 5);
  state = next_staircase_state(rule, state, true, 5);
  EXPECT_EQ(state.index, 3);
  EXPECT_TRUE(state.finished);
  const StaircaseState after = next_staircase_state(rule, state, true, 5);
  EXPECT_EQ(after.index, 3);
  EXPECT_EQ(after.trials, 4);
  // Stopping by reversals.
  StaircaseRule by_reversals;
  by_reversals.max_trials = 0;
  by_reversals.max_reversals = 2;
  by_reversals.reversals_averaged = 2;
  const StaircaseState stopped = replay_staircase(by_reversals, {true, true, false, true, true}, 5);
  EXPECT_EQ(stopped.reversal_indices.size(), 2u);
  EXPECT_TRUE(stopped.finished);
}

TEST(Staircase, BadRulesAreNamedByTheirKey) {
  const auto error = [](StaircaseRule rule, int grid = 8) { return staircase_rule_error(rule, grid).value_or("none"); };
  StaircaseRule rule;
  EXPECT_EQ(error(rule), "none");
  EXPECT_EQ(error(rule, 1), "levels: expected at least two levels for a staircase");
  rule.start_index = 8;
  EXPECT_EQ(error(rule), "start: expected a level of the grid (index 0 to 7)");
  rule = {};
  rule.step_sizes = {2, 0};
  EXPECT_EQ(error(rule), "step_sizes: expected grid steps from 1 to 7, got 0");
  rule = {};
  rule.down = 0;
  EXPECT_EQ(error(rule).rfind("down:", 0), 0u);
  rule = {};
  rule.max_trials = 0;
  EXPECT_EQ(error(rule), "max_trials: expected a stopping rule (max_trials or max_reversals above 0)");
  rule.max_reversals = 4;
  EXPECT_EQ(error(rule), "reversals_averaged: expected at most max_reversals (4)");
  rule = {};
  rule.kind = StaircaseRule::Kind::weighted;
  rule.easier_steps = 0;
  EXPECT_EQ(error(rule).rfind("easier_steps:", 0), 0u);
}

// The grid index at which an observer with p(correct | index) = 1 / (1 + exp((index - 50) / 8))
// answers correctly with probability p.
double index_of_probability(double p) { return 50.0 + 8.0 * std::log(1.0 / p - 1.0); }

// The mean over many simulated staircases of their thresholds (grid indices).
double mean_threshold(const StaircaseRule& rule, int runs, uint64_t seed) {
  std::vector<double> grid(101);
  for (size_t i = 0; i < grid.size(); ++i) grid[i] = double(i);
  Pcg32 random(seed);
  double sum = 0.0;
  int counted = 0;
  for (int run = 0; run < runs; ++run) {
    StaircaseState state = start_staircase(rule);
    while (!state.finished) {
      const double p = 1.0 / (1.0 + std::exp((state.index - 50.0) / 8.0));
      state = next_staircase_state(rule, state, random.uniform() < p, 101);
    }
    if (const auto threshold = staircase_threshold(rule, state, grid)) {
      sum += *threshold;
      ++counted;
    }
  }
  EXPECT_GT(counted, runs * 9 / 10);
  return sum / counted;
}

TEST(Staircase, RulesConvergeWhereLevittAndKaernbachSay) {
  // 500 simulated staircases each, 120 trials, steps 4 then 2, the last 8 reversals averaged. The
  // mean threshold lies within 1.5 grid steps of the index where the observer is right with the
  // rule's probability (a wrong rule is far off: 1-up-1-down converges at 50, 7 steps away from
  // 1-up-2-down's 42.9). Measured: 0.36, 0.38, 0.25 steps off for 1-up-2-, 3- and 1-down; 0.97 for
  // weighted 1/3, whose turning points lie unevenly around its equilibrium (steps of 1 one way, 3
  // the other), so the mean of reversals sits about a step on the easy side.
  StaircaseRule rule;
  rule.start_index = 10;
  rule.step_sizes = {4, 2};
  rule.max_trials = 120;
  rule.reversals_averaged = 8;
  rule.down = 2;
  EXPECT_NEAR(mean_threshold(rule, 500, 1), index_of_probability(std::sqrt(0.5)), 1.5);
  rule.down = 3;
  EXPECT_NEAR(mean_threshold(rule, 500, 2), index_of_probability(std::cbrt(0.5)), 1.5);
  rule.down = 1;
  EXPECT_NEAR(mean_threshold(rule, 500, 3), index_of_probability(0.5), 1.5);
  StaircaseRule weighted = rule;
  weighted.kind = StaircaseRule::Kind::weighted;
  weighted.harder_steps = 1;
  weighted.easier_steps = 3;
  EXPECT_NEAR(mean_threshold(weighted, 500, 4), index_of_probability(0.75), 1.5);
}

}  // namespace
}  // namespace fovlab
