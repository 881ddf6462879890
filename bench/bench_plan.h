#pragma once
// The plan of a fovlab bench sweep: what the flags ask for, typed (BenchOptions, read by
// app/bench_flags), and what bench measures of it (BenchPlan): its units, (scene, scene time, spp)
// in the order they run, and the cells every unit holds, each a method with its variant; and the
// commands that reproduce the sweep and each cell.
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_method.h"
#include "bench/bench_parts.h"
#include "bench/bench_results.h"
#include "core/number_text.h"
#include "foveation/display_geometry.h"
#include "foveation/sampling_map.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::bench {

// Values as `out << value` writes them, comma-separated: a list flag's text ("primitives,columns").
template <typename T>
std::string comma_joined(const std::vector<T>& values) {
  std::ostringstream out;
  for (size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << values[i];
  return out.str();
}

// One FIPR variant of the sweep: periphery refresh x fovea.
struct FiprVariant {
  int refresh = 1;
  double fovea_deg = 0.0;
  FoveationSettings foveation;  // everything but frame_index, for the frame size of the sweep

  std::string fovea_text() const { return format_number(fovea_deg, 6); }  // "7.5"
};

// One sampling model's map of the sweep's frame and gaze (RMFR: one per (f_x, f_y) pair).
struct SamplingVariant {
  SamplingMap map;
  std::string flags;  // the flags that reproduce it ("--sigma 2.6 --fx 0.3 --fy 0.3"), as given
};

// The flags of fovlab bench, read and checked (app/bench_flags.h): typed, lists as numbers.
struct BenchOptions {
  std::vector<std::string> scenes;  // names or .glsl paths
  std::vector<int> spps;
  SphereTraceSettings settings;  // the trace flags; time_s: --time
  // --min-filter and --coarse-test serve IPR and FIPR alike where given (settings' values); a flag not
  // given leaves each method its own default (its descriptor's: with_method_pyramid_defaults, which
  // settings_of applies).
  PyramidFlagsGiven pyramid_flags_given{true, true};
  int repeats = 5;
  std::vector<BenchMethod> methods;  // as given: gt among them, each once
  std::vector<float> times_s;        // --times; empty: --time alone
  // FIPR: the lists as given, and their variants refresh-major (for each refresh, every fovea).
  std::vector<int> refreshes;
  std::vector<double> fovea_degs;
  std::vector<FiprVariant> variants;
  // The sampling models in the order given, each with its maps (RMFR: f_y-major over the pairs).
  std::vector<SamplingVariant> sampling;
  double sigma = 2.6;  // --sigma: each sampling cell's reference is RMFR's shaded samples at it
  std::vector<double> focal_shares_x, focal_shares_y;  // RMFR's --fx and --fy, as given
  ResampleFilter sampling_filter = ResampleFilter::bilinear;
  // The display and gaze the metrics assume (FLIP at its pixels per degree, FPSNR), and FIPR's.
  DisplayGeometry display;
  double gaze_x_px = 0.0;
  double gaze_y_px = 0.0;
  std::string display_line;  // printed above the table: the display, and what was assumed of it
  // The flags that reproduce the display and gaze, the FIPR settings (but --refresh and
  // --fovea-deg), and every sampling model's (with --fx and --fy as swept), as given.
  std::string display_flags, foveation_flags, sampling_flags;
  // --headset CONFIG (issue 42): the eye this sweep renders, "left" or "right"; its view is
  // settings.eye, and display and gaze are on that eye's off-axis image plane. Empty: a flat display.
  std::string eye_name;
  // "--headset CONFIG": in the commands it stands where --width and --height stand for a flat display
  // (the config gives the eye's size); display_flags then hold "--eye NAME" and --gaze, if given.
  std::string headset_flags;
  std::optional<SweepPart> part;  // --cells I/N; none: the whole sweep
  std::filesystem::path json, out_dir;
  std::string device;
  bool require_gpu = false;
  // --step-breakdown: after the timed runs, one untimed frame of GT and of IPR with the step
  // breakdown (SphereTraceSettings::step_breakdown) into their RunsResult.
  bool step_breakdown = false;
  // Writes a measured frame's images into out_dir (colour, step heat map, mask or samples), named by `stem`.
  std::function<void(const std::string& stem, const SphereTraceResult& frame, const SphereTraceSettings& settings)>
      write_frame_images;
};

// One cell of every unit: a method and its variant.
struct BenchCell {
  BenchMethod method = BenchMethod::gt;
  size_t variant = 0;  // fipr: its index in options.variants; a sampling model: in options.sampling
};

struct BenchPlan {
  BenchOptions options;
  std::vector<float> times_s;  // each scene's times: --times, else --time alone
  bool ipr = false;
  bool fipr = false;
  std::vector<BenchCell> unit_cells;  // GT, IPR, every FIPR variant, every sampling map: in the order measured
  double flip_pixels_per_degree = 0.0;

  // Whether the sweep has cells beyond GT against IPR (FIPR variants or sampling models).
  bool has_cells() const { return fipr || !options.sampling.empty(); }
  int units() const { return int(options.scenes.size() * times_s.size() * options.spps.size()); }
  const FiprVariant& variant_of(const BenchCell& cell) const { return options.variants[cell.variant]; }
  const SamplingVariant& sampling_of(const BenchCell& cell) const { return options.sampling[cell.variant]; }
};

// `settings` (of the sweep, with its method set) with that method's depth levels (BenchOptions::pyramid_flags_given).
SphereTraceSettings settings_of(const BenchOptions& options, SphereTraceSettings settings);

// The plan of `options` (checked by the flags' reader; nothing here refuses them).
BenchPlan plan_bench(BenchOptions options);

// What bench checks after the plan and before opening Vulkan: the sweep fits in memory, and every
// scene loads (InputError naming it otherwise). Returns the scenes.
std::vector<SceneSource> load_bench_scenes(const BenchPlan& plan);

// The units and cells of the sweep, in the order fovlab bench runs and writes them: what each part
// of the sweep must hold (bench/bench_parts.h).
SweepLayout sweep_layout(const BenchPlan& plan);

// The command that reproduces the whole sweep, every setting spelled out.
std::string sweep_command(const BenchPlan& plan);
// The command that reproduces one cell with its GT: GT against IPR for one scene, scene time and spp
// (GT's and IPR's cells), one FIPR variant, or one sampling model's map.
std::string cell_command(const BenchPlan& plan, const std::string& scene, float time_s, int spp, const BenchCell& cell);

}  // namespace fovlab::bench
