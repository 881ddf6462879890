#include "study/schedule/staircase.h"

#include <algorithm>
#include <cmath>

namespace fovlab {

std::optional<std::string> staircase_rule_error(const StaircaseRule& rule, int grid_size) {
  if (grid_size < 2) return "levels: expected at least two levels for a staircase";
  if (rule.start_index < 0 || rule.start_index >= grid_size)
    return "start: expected a level of the grid (index 0 to " + std::to_string(grid_size - 1) + ")";
  if (rule.kind == StaircaseRule::Kind::transformed) {
    if (rule.down < 1) return "down: expected 1 or more correct answers in a row";
    if (rule.step_sizes.empty()) return "step_sizes: expected at least one step size";
    for (int step : rule.step_sizes)
      if (step < 1 || step >= grid_size)
        return "step_sizes: expected grid steps from 1 to " + std::to_string(grid_size - 1) + ", got " +
               std::to_string(step);
  } else {
    if (rule.harder_steps < 1 || rule.harder_steps >= grid_size)
      return "harder_steps: expected grid steps from 1 to " + std::to_string(grid_size - 1);
    if (rule.easier_steps < 1 || rule.easier_steps >= grid_size)
      return "easier_steps: expected grid steps from 1 to " + std::to_string(grid_size - 1);
  }
  if (rule.max_trials < 0 || rule.max_reversals < 0) return "max_trials: expected 0 (no limit) or more";
  if (rule.max_trials == 0 && rule.max_reversals == 0)
    return "max_trials: expected a stopping rule (max_trials or max_reversals above 0)";
  if (rule.reversals_averaged < 1) return "reversals_averaged: expected 1 or more";
  // A reversal needs a trial before it and one that turns: at most max_trials - 1 of them.
  if (rule.max_trials > 0 && rule.max_reversals >= rule.max_trials)
    return "max_reversals: expected fewer than max_trials (" + std::to_string(rule.max_trials) +
           "): a staircase makes at most max_trials - 1 reversals, so the stop could never be met";
  if (rule.max_trials > 0 && rule.reversals_averaged >= rule.max_trials)
    return "reversals_averaged: expected fewer than max_trials (" + std::to_string(rule.max_trials) +
           "): a staircase makes at most max_trials - 1 reversals, so it could never have a threshold";
  if (rule.max_reversals > 0 && rule.reversals_averaged > rule.max_reversals)
    return "reversals_averaged: expected at most max_reversals (" + std::to_string(rule.max_reversals) + ")";
  return std::nullopt;
}

double staircase_target_probability(const StaircaseRule& rule) {
  return rule.kind == StaircaseRule::Kind::transformed
             ? std::pow(0.5, 1.0 / rule.down)
             : double(rule.easier_steps) / double(rule.harder_steps + rule.easier_steps);
}

StaircaseState start_staircase(const StaircaseRule& rule) {
  StaircaseState state;
  state.index = rule.start_index;
  return state;
}

StaircaseState next_staircase_state(const StaircaseRule& rule, StaircaseState state, bool correct, int grid_size) {
  if (state.finished) return state;
  ++state.trials;
  int move = 0;  // grid steps, + harder
  if (rule.kind == StaircaseRule::Kind::transformed) {
    const int reversals = static_cast<int>(state.reversal_indices.size());
    const int step = rule.step_sizes[static_cast<size_t>(std::min<int>(reversals, int(rule.step_sizes.size()) - 1))];
    if (correct && ++state.correct_in_row >= rule.down) move = step;
    if (!correct) move = -step;
    if (move != 0) state.correct_in_row = 0;
  } else {
    move = correct ? rule.harder_steps : -rule.easier_steps;
  }
  if (move != 0) {
    const int direction = move > 0 ? 1 : -1;
    if (state.direction != 0 && direction != state.direction) state.reversal_indices.push_back(state.index);
    state.direction = direction;
    state.index = std::clamp(state.index + move, 0, grid_size - 1);
  }
  state.finished = (rule.max_trials > 0 && state.trials >= rule.max_trials) ||
                   (rule.max_reversals > 0 && static_cast<int>(state.reversal_indices.size()) >= rule.max_reversals);
  return state;
}

StaircaseState replay_staircase(const StaircaseRule& rule, const std::vector<bool>& answers, int grid_size) {
  StaircaseState state = start_staircase(rule);
  for (const bool correct : answers) state = next_staircase_state(rule, state, correct, grid_size);
  return state;
}

std::optional<double> staircase_threshold(const StaircaseRule& rule, const StaircaseState& state,
                                          const std::vector<double>& levels) {
  const size_t count = static_cast<size_t>(rule.reversals_averaged);
  if (state.reversal_indices.size() < count) return std::nullopt;
  double sum = 0.0;
  for (size_t i = state.reversal_indices.size() - count; i < state.reversal_indices.size(); ++i)
    sum += levels.at(static_cast<size_t>(state.reversal_indices[i]));
  return sum / static_cast<double>(count);
}

}  // namespace fovlab
