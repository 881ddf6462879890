#pragma once
// fovlab bench's interface, what app/ calls (the layer test lets app/ include only bench's interface
// headers, tests/layers/check_layers.cmake). A sweep: the flags read into BenchOptions
// (app/bench_flags.h) -> plan_bench -> load_bench_scenes -> run_bench (a BenchReport of typed units
// and cells) -> the part's JSON (write_bench_part), or the sweep's JSON, tables and charts
// (finish_sweep). bench-merge: parts' JSON -> merge_bench_parts (each part checked against the
// sweep_layout its command plans) -> finish_sweep.
#include <functional>
#include <string>
#include <vector>

#include "bench/bench_json.h"
#include "bench/bench_method.h"
#include "bench/bench_outputs.h"
#include "bench/bench_parts.h"
#include "bench/bench_plan.h"
#include "bench/bench_results.h"

namespace fovlab::bench {

// The units the run measures: the plan's, or its part's.
int units_measured(const BenchPlan& plan);

// Opens the Vulkan device the options name and measures every unit of the plan (of its part with
// --cells), printing each row or cell as it is measured; `progress` is told each unit. Writes the
// frames' images through options.write_frame_images when out_dir is set. runtime_error after a
// Vulkan validation message.
BenchReport run_bench(const BenchPlan& plan, const std::vector<SceneSource>& scenes,
                      const std::function<void(const std::string& unit)>& progress);

}  // namespace fovlab::bench
