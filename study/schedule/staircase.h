#pragma once
// Adaptive staircases on a study's level grid (issue 19, first step): Levitt's (1971) transformed
// up-down rules (1-up-N-down) and Kaernbach's (1991) weighted up-down. A staircase is a pure
// function of its rule and the answers so far: next_staircase_state folds one answer in, so a
// session resumed or replayed from its log rebuilds the same levels from the logged answers.
//
// The grid runs from the easiest level (index 0: least like the reference, the difference easiest
// to see) to the hardest. A correct answer (the difference was seen) moves the staircase toward
// harder levels, a wrong one toward easier; moves stop at the grid's ends.
//   transformed  `down` correct answers in a row: step_sizes[r] steps harder; a wrong answer:
//                step_sizes[r] steps easier (r: reversals so far, the last size kept). Converges
//                where p(correct) = 0.5^(1/down): 0.7071 for 1-up-2-down, 0.7937 for 1-up-3-down.
//   weighted     each correct answer: harder_steps harder; each wrong one: easier_steps easier.
//                Converges where p(correct) = easier_steps / (harder_steps + easier_steps) (0.75
//                for 1 and 3).
// A reversal is a move against the direction of the move before; its level is the level of the
// trial whose answer turned the staircase. The threshold is the mean of the last
// `reversals_averaged` reversal levels.
#include <optional>
#include <string>
#include <vector>

namespace fovlab {

struct StaircaseRule {
  enum class Kind { transformed, weighted };
  Kind kind = Kind::transformed;
  int down = 2;                       // transformed: correct answers in a row for one step harder
  std::vector<int> step_sizes = {1};  // transformed: grid steps, the r-th after r reversals
  int harder_steps = 1;               // weighted
  int easier_steps = 3;               // weighted
  int start_index = 0;                // grid index of the first trial
  int max_trials = 50;                // stops after this many trials (0: no limit)
  int max_reversals = 0;              // stops after this many reversals (0: no limit)
  int reversals_averaged = 6;         // the threshold's reversals
};

struct StaircaseState {
  int index = 0;                      // grid index of the next trial
  int trials = 0;                     // answers folded in
  int correct_in_row = 0;             // transformed: correct answers since the last move
  int direction = 0;                  // the last move: +1 harder, -1 easier, 0 none yet
  std::vector<int> reversal_indices;  // grid index of each reversal, in order
  bool finished = false;              // a stopping rule is met
};

// What is wrong with a rule on a grid of `grid_size` levels, as "KEY: expected ..." for a config
// error, or nullopt: a start outside the grid, a step or `down` below 1, no stopping rule, or a
// threshold that averages more reversals than the staircase may make.
std::optional<std::string> staircase_rule_error(const StaircaseRule& rule, int grid_size);

// The p(correct) the rule converges to: 0.5^(1/down), or easier / (harder + easier).
double staircase_target_probability(const StaircaseRule& rule);

StaircaseState start_staircase(const StaircaseRule& rule);
// The state after one more answer. The rule must be valid for the grid (staircase_rule_error).
StaircaseState next_staircase_state(const StaircaseRule& rule, StaircaseState state, bool correct, int grid_size);
// The state after every answer in order, from the start.
StaircaseState replay_staircase(const StaircaseRule& rule, const std::vector<bool>& answers, int grid_size);

// The mean level (`levels`: the grid, easiest first) of the last reversals_averaged reversals;
// nullopt with fewer reversals than that.
std::optional<double> staircase_threshold(const StaircaseRule& rule, const StaircaseState& state,
                                          const std::vector<double>& levels);

}  // namespace fovlab
