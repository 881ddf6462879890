#include "analysis/study/rating_grid.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace fovlab::analysis {
namespace {

// Means this close (scores are 1-3) are the same mean: a tie for the best pair.
constexpr double kTieTolerance = 1e-9;

size_t index_of(const std::vector<double>& values, double value) {
  return static_cast<size_t>(std::lower_bound(values.begin(), values.end(), value) - values.begin());
}

// One participant's scores in one cell.
struct Sums {
  double sum = 0.0;
  uint64_t count = 0;
};

// Over participants: the sum of their cell means, and how many trials and participants.
struct CellTotals {
  double sum_of_means = 0.0;
  uint64_t trials = 0;
  int participants = 0;
};

// A map's key: its scene and its level (none: every level).
using MapKey = std::pair<std::string, std::optional<double>>;

std::vector<size_t> best_cells(const std::vector<GridCell>& cells) {
  std::optional<double> highest;
  for (const GridCell& cell : cells)
    if (cell.mean_score && (!highest || *cell.mean_score > *highest)) highest = cell.mean_score;
  std::vector<size_t> best;
  if (!highest) return best;
  for (size_t i = 0; i < cells.size(); ++i)
    if (cells[i].mean_score && *cells[i].mean_score >= *highest - kTieTolerance) best.push_back(i);
  return best;
}

}  // namespace

std::optional<ParameterGrid> find_parameter_grid(RenderMethod test_method, const std::string& level_parameter,
                                                 const std::vector<VariantConfig>& variants) {
  if (variants.size() < 4) return std::nullopt;  // two values on each axis at least
  const ParameterLayer& first = variants.front().parameters;
  for (const VariantConfig& variant : variants) {
    if (variant.parameters.size() != first.size()) return std::nullopt;
    for (const auto& [key, value] : first)
      if (!variant.parameters.count(key)) return std::nullopt;
  }
  std::vector<std::string> varying;  // std::map order: alphabetical
  for (const auto& [key, value] : first) {
    const bool varies = std::any_of(variants.begin(), variants.end(),
                                    [&](const VariantConfig& variant) { return variant.parameters.at(key) != value; });
    if (varies) varying.push_back(key);
  }
  if (varying.size() != 2) return std::nullopt;
  const MethodDescriptor& method = describe(test_method);
  for (const std::string& key : varying) {
    const ParameterDescriptor* parameter = find_parameter(method, key);
    if (!parameter || parameter->type == ParameterType::choice || key == level_parameter) return std::nullopt;
  }
  ParameterGrid grid;
  grid.x_key = varying[0];
  grid.y_key = varying[1];
  std::set<double> xs, ys;
  for (const VariantConfig& variant : variants) {
    const double x = variant.parameters.at(grid.x_key);
    const double y = variant.parameters.at(grid.y_key);
    if (!std::isfinite(x) || !std::isfinite(y)) return std::nullopt;
    xs.insert(x);
    ys.insert(y);
  }
  grid.x_values.assign(xs.begin(), xs.end());
  grid.y_values.assign(ys.begin(), ys.end());
  if (grid.x_values.size() < 2 || grid.y_values.size() < 2 ||
      grid.x_values.size() * grid.y_values.size() != variants.size())
    return std::nullopt;
  std::set<size_t> taken;
  for (const VariantConfig& variant : variants) {
    const size_t column = index_of(grid.x_values, variant.parameters.at(grid.x_key));
    const size_t row = index_of(grid.y_values, variant.parameters.at(grid.y_key));
    const size_t cell = row * grid.x_values.size() + column;
    if (!taken.insert(cell).second) return std::nullopt;  // a pair set twice (so another is missing)
    grid.cell_of_variant.push_back(cell);
  }
  return grid;
}

std::optional<RatingGrid> rating_grid(const StudyData& data) {
  if (data.protocol != ProtocolKind::rating) return std::nullopt;
  const std::optional<ParameterGrid> grid = find_parameter_grid(data.test_method, data.level_parameter, data.variants);
  if (!grid) return std::nullopt;
  std::map<std::string, size_t> cell_of_variant;
  for (size_t v = 0; v < data.variants.size(); ++v) cell_of_variant[data.variants[v].name] = grid->cell_of_variant[v];
  const size_t cell_count = grid->x_values.size() * grid->y_values.size();

  // The scenes of the included participants' trials: several are also pooled as "all".
  std::set<std::string> scenes;
  for (const ParticipantData& participant : data.participants)
    if (!participant.excluded)
      for (const StudyTrial& trial : participant.trials) scenes.insert(trial.scene);
  const bool pool_scenes = scenes.size() > 1;
  const std::string pooled = "all";

  // First each participant's mean score per map and cell, then the mean of those over participants
  // (Ye et al. 2022, 4.4.1: per participant averaged over sigma, then over participants).
  // A conditions file may test the cells at levels of their own: a map over all levels would then
  // compare cells averaged over different levels, so it is made only when every cell has the same.
  const bool same_levels = std::all_of(data.variants.begin(), data.variants.end(), [&](const VariantConfig& variant) {
    return data.levels_of(variant.name) == data.levels_of(data.variants.front().name);
  });
  std::map<MapKey, std::vector<CellTotals>> totals;
  for (const ParticipantData& participant : data.participants) {
    if (participant.excluded) continue;
    std::map<MapKey, std::vector<Sums>> sums;
    for (const StudyTrial& trial : participant.trials) {
      if (trial.attention_check || trial.answers.empty()) continue;
      const std::string& answer = trial.answers.back();
      if (answer.empty() || !data.rules().is_answer(answer)) continue;  // a timeout
      const auto cell = cell_of_variant.find(trial.variant);
      if (cell == cell_of_variant.end()) continue;
      const double score = std::stod(answer);
      std::vector<MapKey> keys;
      if (same_levels || !trial.level) keys.push_back({trial.scene, std::nullopt});
      if (trial.level) keys.push_back({trial.scene, trial.level});
      if (pool_scenes) {
        if (same_levels || !trial.level) keys.push_back({pooled, std::nullopt});
        if (trial.level) keys.push_back({pooled, trial.level});
      }
      for (const MapKey& key : keys) {
        std::vector<Sums>& cells = sums[key];
        cells.resize(cell_count);
        cells[cell->second].sum += score;
        ++cells[cell->second].count;
      }
    }
    for (const auto& [key, cells] : sums) {
      std::vector<CellTotals>& cell_totals = totals[key];
      cell_totals.resize(cell_count);
      for (size_t c = 0; c < cell_count; ++c) {
        if (cells[c].count == 0) continue;
        cell_totals[c].sum_of_means += cells[c].sum / double(cells[c].count);
        cell_totals[c].trials += cells[c].count;
        ++cell_totals[c].participants;
      }
    }
  }

  RatingGrid result;
  result.x_key = grid->x_key;
  result.y_key = grid->y_key;
  result.x_values = grid->x_values;
  result.y_values = grid->y_values;
  const auto add_maps_of = [&](const std::string& scene) {
    for (const auto& [key, cell_totals] : totals) {  // the level none first, then ascending
      if (key.first != scene) continue;
      GridMap map;
      map.scene = scene;
      map.level = key.second;
      for (size_t c = 0; c < cell_count; ++c) {
        GridCell cell;
        cell.x = grid->x_values[c % grid->x_values.size()];
        cell.y = grid->y_values[c / grid->x_values.size()];
        const CellTotals& total = cell_totals[c];
        if (total.participants > 0) cell.mean_score = total.sum_of_means / double(total.participants);
        cell.trials = total.trials;
        cell.participants = total.participants;
        map.cells.push_back(cell);
      }
      map.best = best_cells(map.cells);
      result.maps.push_back(std::move(map));
    }
  };
  for (const std::string& scene : scenes) add_maps_of(scene);
  if (pool_scenes) add_maps_of(pooled);
  return result;
}

}  // namespace fovlab::analysis
