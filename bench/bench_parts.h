#pragma once
// A benchmark sweep split into parts (fovlab bench --cells I/N) and joined again (fovlab
// bench-merge), so N cluster tasks give the table, charts and Pareto fronts of one run
// (docs/scale-out.md).
//
// A sweep is a list of units, (scene, scene time, spp) in the order bench runs them; a unit holds
// every cell of its methods (GT, IPR, each FIPR variant, each sampling model), because a cell's
// speed-up and errors are measured against its unit's GT frame and GT is timed interleaved with IPR.
// Part I of N holds units I, I + N, I + 2N, ... (interleaved, so a slow scene is spread over the
// parts). A part's JSON is bench's report of its units plus "part": {"index", "count", "units"}.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

struct PartReport {
  std::string path;  // names the part in errors
  nlohmann::json report;
};

// The report one run of the whole sweep would have written: every part's rows and cells in the
// sweep's order, "part" gone, every other field as the parts have it (Pareto marks are the caller's,
// over all cells). InputError naming the file when a file is not a part, a part is missing or given
// twice, parts come from different sweeps or devices, or a part's rows and cells are not its units'.
nlohmann::json merge_bench_parts(const std::vector<PartReport>& parts);

}  // namespace fovlab::bench
