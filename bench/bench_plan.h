#pragma once
// The plan of a fovlab bench sweep, once its flags are checked (app/bench_plan.h makes it): the
// methods, the FIPR variants, the sampling models' maps, and the display and gaze the error metrics
// assume.
#include <string>
#include <vector>

#include "core/number_text.h"
#include "bench/bench_parts.h"
#include "foveation/display_geometry.h"
#include "foveation/sampling_map.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::bench {

// One FIPR variant of the sweep: periphery refresh x fovea.
struct FiprVariant {
  int refresh = 1;
  double fovea_deg = 0.0;
  FoveationSettings foveation;  // everything but frame_index, for the frame size of the sweep

  std::string fovea_text() const { return format_number(fovea_deg, 6); }  // "7.5"
};

struct BenchPlan {
  bool ipr = false;
  bool fipr = false;
  std::vector<int> refreshes;       // as given, in order
  std::vector<double> fovea_degs;   // as given, in order
  std::vector<FiprVariant> variants;  // refresh-major: for each refresh, every fovea
  std::vector<float> times_s;         // scene times of each scene's cells (--times; else --time alone)
  // Seed 002's sampling models in the order given, each with its map of the sweep's frame and gaze
  // (RMFR: one map per (f_x, f_y) pair, f_y-major).
  std::vector<SamplingMap> sampling_maps;
  std::vector<double> focal_shares_x, focal_shares_y;  // RMFR's, as given
  SamplingSettings sampling;  // the flags they were made with

  // Whether the sweep has cells beyond GT against IPR (FIPR variants or sampling models).
  bool has_cells() const { return fipr || !sampling_maps.empty(); }
  // The display and gaze the metrics assume (FLIP at its pixels per degree, FPSNR), and FIPR's.
  DisplayGeometry display;
  double gaze_x_px = 0.0;
  double gaze_y_px = 0.0;
  double flip_pixels_per_degree = 0.0;
  std::optional<SweepPart> part;  // --cells I/N; none: the whole sweep
};

}  // namespace fovlab::bench
