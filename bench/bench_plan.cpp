#include "bench/bench_plan.h"

#include <algorithm>
#include <cstdint>
#include <sstream>
#include <utility>

#include "core/memory_budget.h"
#include "core/number_text.h"

namespace fovlab::bench {

namespace {

// The sampling models of a plan, in order, each once (RMFR's several maps, a focal sweep, are one).
std::vector<SamplingModel> sampling_models(const BenchPlan& plan) {
  std::vector<SamplingModel> models;
  for (const SamplingVariant& variant : plan.options.sampling)
    if (std::find(models.begin(), models.end(), model_of(variant.map)) == models.end())
      models.push_back(model_of(variant.map));
  return models;
}

// "gt,ipr,fipr,rmfr,...": the methods of a plan, as --methods takes them.
std::string methods_text(const BenchPlan& plan, bool with_ipr, bool with_fipr) {
  std::string text = with_ipr ? "gt,ipr" : "gt";
  if (with_fipr) text += ",fipr";
  for (SamplingModel model : sampling_models(plan))
    text += std::string(",") + bench_method_name(bench_method_of(model));
  return text;
}

std::string time_flag(float time_s) { return "--time " + exact_number_text(time_s); }

// A word of a command as a shell (and CLI11's split_up) reads it back: quoted when it holds a space.
std::string command_word(const std::string& word) {
  if (word.find_first_of(" \t") == std::string::npos) return word;
  return word.find('\'') == std::string::npos ? "'" + word + "'" : "\"" + word + "\"";
}

// `time_text`: "--time T" or "--times A,B,...".
std::string command_text(const BenchOptions& options, const std::string& scenes, const std::string& spps,
                         const std::string& methods, const std::string& time_text) {
  const SphereTraceSettings& s = options.settings;
  std::ostringstream out;
  out << "fovlab bench --scenes " << command_word(scenes) << " --spp " << spps;
  if (options.headset_flags.empty()) out << " --width " << s.width << " --height " << s.height;
  else out << " " << options.headset_flags;
  out << " --repeats " << options.repeats << " " << time_text << " --levels " << s.pyramid_levels;
  // A flag not given stays out: each method takes its own default again.
  if (options.pyramid_flags_given.min_filter) out << " --min-filter " << s.min_filter_size;
  if (options.pyramid_flags_given.coarse_test) out << " --coarse-test " << coarse_test_name(s.coarse_test);
  out << (s.full_resolution_depth ? " --full-depth" : "") << " --max-steps " << s.max_steps << " --hit-threshold "
      << exact_number_text(s.hit_threshold) << " --methods " << methods;
  return out.str();
}

// What a sweep holds at once, at least: one tracer layout (the largest of its methods: they share
// the tracer, which frees a layout before making the next), and the results of GT, IPR and a FIPR
// frame with the display images the errors compare.
uint64_t bench_memory_bytes(const BenchPlan& plan) {
  SphereTraceSettings settings = plan.options.settings;
  const std::vector<int>& spps = plan.options.spps;
  if (!spps.empty())
    settings.samples_per_pixel = *std::max_element(spps.begin(), spps.end());  // the floor keeps a depth a sample
  uint64_t layout_bytes = 0;
  uint64_t results_bytes = 0;
  const uint64_t frame_pixels = uint64_t(settings.width) * uint64_t(settings.height);
  std::vector<SphereTraceSettings> methods;
  settings.method = TraceMethod::ground_truth;
  methods.push_back(settings);
  settings.one_step_floor = true;
  methods.push_back(settings);
  settings.one_step_floor = false;
  settings.method = TraceMethod::inverted_pyramid;
  if (plan.ipr) methods.push_back(settings_of(plan.options, settings));
  if (plan.fipr && !plan.options.variants.empty()) {
    settings.method = TraceMethod::foveated_pyramid;
    settings.foveation = plan.options.variants.front().foveation;
    methods.push_back(settings_of(plan.options, settings));
  }
  for (const SphereTraceSettings& method : methods) {
    layout_bytes = std::max(layout_bytes, render_memory_bytes(method));
    results_bytes += frame_pixels * sizeof(float) * (method.method == TraceMethod::foveated_pyramid ? 5 : 4);
  }
  return layout_bytes + results_bytes + 2 * frame_pixels * 3 * sizeof(float);  // + GT's and a test's display image
}

}  // namespace

SphereTraceSettings settings_of(const BenchOptions& options, SphereTraceSettings settings) {
  return with_method_pyramid_defaults(settings, settings.method, options.pyramid_flags_given);
}

BenchPlan plan_bench(BenchOptions options) {
  BenchPlan plan;
  plan.options = std::move(options);
  const BenchOptions& o = plan.options;
  const auto has = [&](BenchMethod method) {
    return std::find(o.methods.begin(), o.methods.end(), method) != o.methods.end();
  };
  plan.ipr = has(BenchMethod::ipr);
  plan.fipr = has(BenchMethod::fipr);
  plan.times_s = o.times_s.empty() ? std::vector<float>{o.settings.time_s} : o.times_s;
  plan.flip_pixels_per_degree = o.display.pixels_per_degree_at_principal_point();  // the centre on a flat display
  // As a unit is measured: GT, IPR, every FIPR variant, every sampling model's map.
  plan.unit_cells.push_back({BenchMethod::gt});
  if (plan.ipr) plan.unit_cells.push_back({BenchMethod::ipr});
  if (plan.fipr)
    for (size_t index = 0; index < o.variants.size(); ++index) plan.unit_cells.push_back({BenchMethod::fipr, index});
  for (size_t index = 0; index < o.sampling.size(); ++index)
    plan.unit_cells.push_back({bench_method_of(model_of(o.sampling[index].map)), index});
  return plan;
}

std::vector<SceneSource> load_bench_scenes(const BenchPlan& plan) {
  const SphereTraceSettings& settings = plan.options.settings;
  check_memory_fits(bench_memory_bytes(plan),
                    "--width x --height = " + std::to_string(settings.width) + "x" + std::to_string(settings.height),
                    "lower --width and --height");
  std::vector<SceneSource> scenes;
  for (const std::string& name : plan.options.scenes) scenes.push_back(load_scene(name));
  return scenes;
}

SweepLayout sweep_layout(const BenchPlan& plan) {
  const BenchOptions& o = plan.options;
  SweepLayout layout;
  for (const std::string& scene : o.scenes) layout.scenes.push_back(scene_name(scene));
  layout.times_s = plan.times_s;
  layout.spps = o.spps;
  layout.width = o.settings.width;
  layout.height = o.settings.height;
  layout.repeats = o.repeats;
  if (!o.sampling.empty()) {
    layout.focal_shares_x = o.focal_shares_x;
    layout.focal_shares_y = o.focal_shares_y;
  }
  for (const BenchCell& cell : plan.unit_cells) {
    PlannedCell planned{cell.method};
    if (cell.method == BenchMethod::fipr) {
      planned.refresh = plan.variant_of(cell).refresh;
      planned.fovea_deg = plan.variant_of(cell).fovea_deg;
    } else if (sampling_model_of(cell.method)) {
      if (const auto* rmfr = std::get_if<RectangularMapping>(&plan.sampling_of(cell).map)) {
        planned.focal_share_x = rmfr->x.focal_share;
        planned.focal_share_y = rmfr->y.focal_share;
      }
    }
    layout.unit_cells.push_back(planned);
  }
  return layout;
}

std::string sweep_command(const BenchPlan& plan) {
  const BenchOptions& o = plan.options;
  // As given: a merge rebuilds the sweep's cells from its command (exact_number_text reads back the same).
  const std::string times = exact_numbers_text(plan.times_s);
  const std::string time_text = o.times_s.empty() ? time_flag(o.settings.time_s) : "--times " + times;
  std::string text =
      command_text(o, comma_joined(o.scenes), comma_joined(o.spps), methods_text(plan, plan.ipr, plan.fipr), time_text);
  if (!o.sampling.empty()) text += " " + o.sampling_flags;
  if (o.step_breakdown) text += " --step-breakdown";
  if (o.settings.over_relaxation != 1.0f) text += " --over-relax " + exact_number_text(o.settings.over_relaxation);
  if (!plan.fipr) return text + " " + o.display_flags;
  return text + " --refresh " + comma_joined(o.refreshes) + " --fovea-deg " + exact_numbers_text(o.fovea_degs) + " " +
         o.foveation_flags;
}

std::string cell_command(const BenchPlan& plan, const std::string& scene, float time_s, int spp,
                         const BenchCell& cell) {
  const BenchOptions& o = plan.options;
  const std::string time_text = time_flag(time_s);
  const std::string spp_text = std::to_string(spp);
  if (sampling_model_of(cell.method)) {
    return command_text(o, scene, spp_text, std::string("gt,") + bench_method_name(cell.method), time_text) + " " +
           plan.sampling_of(cell).flags + " " + o.display_flags;
  }
  if (cell.method != BenchMethod::fipr) {
    const std::string relax = o.settings.over_relaxation != 1.0f
                                  ? " --over-relax " + exact_number_text(o.settings.over_relaxation)
                                  : std::string();
    return command_text(o, scene, spp_text, plan.ipr ? "gt,ipr" : "gt", time_text) + relax + " " + o.display_flags;
  }
  const FiprVariant& variant = plan.variant_of(cell);
  return command_text(o, scene, spp_text, "gt,fipr", time_text) + " --refresh " + std::to_string(variant.refresh) +
         " --fovea-deg " + exact_number_text(variant.fovea_deg) + " " + o.foveation_flags;
}

}  // namespace fovlab::bench
