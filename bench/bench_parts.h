#pragma once
// A benchmark sweep split into parts (fovlab bench --cells I/N) and joined again (fovlab
// bench-merge), so N cluster tasks give the table, charts and Pareto fronts of one run
// (docs/scale-out.md).
//
// A sweep is a list of units, (scene, scene time, spp) in the order bench runs them; a unit holds
// every cell of its methods (GT, IPR, each FIPR variant, each sampling model), because a cell's
// speed-up and errors are measured against its unit's GT frame and GT is timed interleaved with IPR.
// Part I of N holds units I, I + N, I + 2N, ... (interleaved, so a slow scene is spread over the
// parts). A part's JSON is bench's report of its units plus "part": {"index", "count", "units"}; its
// "command" (every flag of the sweep) says which units and cells a part of each index holds.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/bench_method.h"

namespace fovlab::bench {

struct SweepPart {
  int index = 0;  // 0-based
  int count = 1;
  bool holds(int unit) const { return unit % count == index; }
  // How many of `units` this part holds.
  int units_held(int units) const { return index < units ? (units - index + count - 1) / count : 0; }
};

// The report's "part" object.
nlohmann::json part_json(const SweepPart& part, int units);

// One cell of every unit, as the sweep's plan makes it: the method and the variant it measures.
struct PlannedCell {
  BenchMethod method = BenchMethod::gt;
  std::optional<int> refresh;           // fipr's periphery refresh
  std::optional<double> fovea_deg;      // fipr's fovea
  std::optional<double> focal_share_x;  // rmfr's pair
  std::optional<double> focal_share_y;
};

// What a sweep's flags plan (bench/bench_plan.h sweep_layout): its units, (scene, time, spp) in the
// order bench runs them, scene-major then time then spp, and the cells of each unit, in order.
struct SweepLayout {
  std::vector<std::string> scenes;  // as rows name them: a built-in name, or a file's stem
  std::vector<float> times_s;
  std::vector<int> spps;
  std::vector<PlannedCell> unit_cells;
  // RMFR's --fx and --fy lists (the report's "sampling_focal_shares"), empty without a sampling model.
  std::vector<double> focal_shares_x;
  std::vector<double> focal_shares_y;
  int width = 0;
  int height = 0;
  int repeats = 0;

  int units() const { return int(scenes.size() * times_s.size() * spps.size()); }
  const std::string& scene_of(int unit) const { return scenes[size_t(unit) / (times_s.size() * spps.size())]; }
  float time_of(int unit) const { return times_s[size_t(unit) / spps.size() % times_s.size()]; }
  int spp_of(int unit) const { return spps[size_t(unit) % spps.size()]; }
};

struct PartReport {
  std::string path;  // names the part in errors
  nlohmann::json report;
};

// The layout of the sweep whose part this is, rebuilt from the flags the part records (its
// "command"); InputError naming the part when they are not a sweep's.
using PartLayout = std::function<SweepLayout(const PartReport& part)>;

// The longest median GPU time of a frame a part may hold, in milliseconds: a day. A task that timed
// frames longer than that would have run for days per unit (every method --repeats times, GT twice
// more), beyond any cluster's time limit; and a time of 1e308 would overflow the sums and ratios
// the tables and charts make of the times.
inline constexpr double kMaxFrameGpuMs = 24.0 * 3600.0 * 1000.0;

// The report one run of the whole sweep would have written: every part's rows and cells in the
// sweep's order, "part" gone, every other field as the parts have it (Pareto marks are the caller's,
// over all cells). InputError naming the file and the field when a file is not a part, a part is
// missing or given twice, parts come from different sweeps or devices, or a part's rows and cells
// are not those of its units in the sweep that `layout_of` rebuilds from its flags (its index
// relabelled, a method or variant the flags do not plan), or a time is negative or over
// kMaxFrameGpuMs.
nlohmann::json merge_bench_parts(const std::vector<PartReport>& parts, const PartLayout& layout_of);

}  // namespace fovlab::bench
