#pragma once
// What fovlab bench measures, typed, from the run to the report: per unit (scene, scene time, spp)
// GT, the one-step floor and IPR (a row of the JSON's "rows"), and per cell (the JSON's "cells") its
// method's times, steps and errors against the unit's GT frame. bench/bench_json.h writes them.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_method.h"
#include "bench/bench_parts.h"
#include "bench/frame_errors.h"
#include "foveation/display_geometry.h"
#include "foveation/sampling_map.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::bench {

// One method's timings over the repeats and the measured frame's steps.
struct RunsResult {
  double median_gpu_ms = 0.0;
  double median_wall_ms = 0.0;
  std::vector<double> gpu_ms_runs;
  std::map<std::string, double> median_pass_gpu_ms;
  uint64_t total_steps = 0;
  double steps_per_pixel = 0.0;
  double steps_per_sample = 0.0;
  uint64_t capped_rays = 0;
  uint64_t restarted_rays = 0;
  std::optional<StepBreakdown> step_breakdown;  // --step-breakdown (GT and IPR): the measured frame's
};

// A FIPR cell's sequence (bench/bench_runs.h time_fipr_sequence) and its last timed frame.
struct FiprCellResult {
  int refresh = 1;
  double fovea_deg = 0.0;
  double kept_share = 0.0;
  FoveationSettings foveation;  // frame_index: the measured frame's
  FoveationStats stats;
  double pixels = 0.0;
  int warmup_frames = 0;
  uint32_t first_timed_frame = 0;
  uint32_t last_timed_frame = 0;
};

// A sampling model's cell: what its map samples and what the frame shaded.
struct SamplingCellResult {
  SamplingModel model = SamplingModel::rectangular;
  uint64_t shaded_samples = 0;
  double shaded_share = 0.0;
  double theoretical_speedup = 1.0;
  double effective_speedup = 1.0;
  double mean_density = 1.0;
  std::optional<double> focal_share_x, focal_share_y;  // RMFR's pair
  // The reference: RMFR's shaded samples at the run's sigma on this frame (its buffer, whether or not
  // RMFR is in the run), what --equalise matches.
  double reference_sigma = 0.0;
  uint64_t reference_shaded_samples = 0;
};

struct CellResult {
  BenchMethod method = BenchMethod::gt;
  std::string scene;
  int spp = 1;
  float time_s = 0.0f;
  RunsResult runs;
  double gt_median_gpu_ms = 0.0;
  double speedup = 1.0;
  FrameErrors errors;  // against the unit's GT frame (GT's own: identical)
  double top_level_share = 1.0;
  double refreshed_share = 0.0;
  std::optional<FiprCellResult> fipr;
  std::optional<SamplingCellResult> sampling;
  std::string command;  // reproduces the cell with its GT
};

// GT against IPR for one unit, and the one-step floor (SphereTraceSettings::one_step_floor).
struct UnitResult {
  std::string scene;
  int spp = 1;
  float time_s = 0.0f;
  RunsResult gt;
  RunsResult floor;
  double floor_ssim_against_gt = 1.0;
  double gt_over_floor = 1.0;
  std::optional<RunsResult> ipr;  // with IPR in the sweep:
  double speedup = 1.0;
  double ipr_over_floor = 1.0;
  FrameErrors errors;
};

// A sweep's (or with --cells a part's) results and the settings they were measured with.
// One method's depth levels (IPR, FIPR): --min-filter and --coarse-test where given, else the
// method's own defaults.
struct PyramidChoices {
  int min_filter_size = 3;
  CoarseTest coarse_test = CoarseTest::centre_ray;
};

struct BenchReport {
  std::string device;
  bool timestamps = false;
  SphereTraceSettings settings;  // the trace flags (time_s: --time)
  // A flag of the two not given: the JSON gives each pyramid method's own value (ipr, fipr as run).
  bool min_filter_given = true, coarse_test_given = true;
  std::vector<std::pair<BenchMethod, PyramidChoices>> pyramids;
  int repeats = 0;
  std::vector<float> times_s;
  std::string command;               // the sweep's
  std::string eye_name;              // --headset: "left" or "right" (its view: settings.eye); else empty
  std::vector<BenchMethod> methods;  // as given
  double flip_pixels_per_degree = 0.0;
  DisplayGeometry display;
  double gaze_x_px = 0.0, gaze_y_px = 0.0;
  bool fipr = false;
  std::vector<int> refreshes;
  std::vector<double> fovea_degs;
  bool sampling = false;
  std::vector<double> focal_shares_x, focal_shares_y;
  std::optional<SweepPart> part;
  int units = 0;  // the sweep's
  std::vector<UnitResult> rows;
  std::vector<CellResult> cells;
};

}  // namespace fovlab::bench
