// fovlab bench: ground truth against the inverted pyramid (IPR), its foveated form (FIPR) and seed
// 002's sampling models (rmfr, hyperbolic, linear, kfr), scene by scene and spp by spp (and, for
// FIPR, periphery refresh by fovea): median GPU milliseconds,
// speed-up, GT's and IPR's time over the one-step floor (every sample one step from where GT's own
// trace stopped, then shaded: SphereTraceSettings::one_step_floor), steps per pixel, and SSIM, PSNR,
// FLIP and FPSNR against GT; where the time goes; the
// trade-off between speed and error as charts with their Pareto fronts.
//
// The steps live in their own files: flags checked into a plan (bench_plan), frames timed and
// measured (bench_runs), Pareto fronts and charts (bench_pareto), Markdown tables (bench_report),
// the tables, charts and files of a finished sweep (bench_outputs, shared with bench-merge), a sweep
// in parts (bench_parts). This file registers the flags and runs the sweep, or with --cells I/N one
// part of it.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench_outputs.h"
#include "app/bench_plan.h"
#include "bench/bench_report.h"
#include "bench/bench_runs.h"
#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "app/render_outputs.h"
#include "core/atomic_file.h"
#include "core/image_io.h"
#include "core/memory_budget.h"
#include "core/number_text.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

using namespace fovlab::bench;  // the benchmark library this command prints

namespace {

nlohmann::json display_json(const BenchPlan& plan) {
  return {{"width_mm", plan.display.width_mm},
          {"height_mm", plan.display.height_mm},
          {"viewing_distance_mm", plan.display.viewing_distance_mm},
          {"pixels_per_degree_at_centre", plan.display.pixels_per_degree_at_centre()}};
}

// GT's own cell: the reference, so its errors are those of identical frames.
nlohmann::json gt_cell(const std::string& scene, int spp, const nlohmann::json& runs) {
  nlohmann::json cell = {{"method", "gt"}, {"scene", scene}, {"spp", spp}};
  cell.update(runs);
  cell["gt_median_gpu_ms"] = runs["median_gpu_ms"];
  cell["speedup"] = 1.0;
  cell.update(FrameErrors{}.json());
  cell["top_level_share"] = 1.0;
  cell["refreshed_share"] = 0.0;
  return cell;
}

nlohmann::json measured_cell(const std::string& method, const std::string& scene, int spp, const nlohmann::json& runs,
                             double gt_median_gpu_ms, const FrameErrors& errors) {
  nlohmann::json cell = {{"method", method}, {"scene", scene}, {"spp", spp}};
  cell.update(runs);
  cell["gt_median_gpu_ms"] = gt_median_gpu_ms;
  cell["speedup"] = gt_median_gpu_ms / runs["median_gpu_ms"].get<double>();
  cell.update(errors.json());
  return cell;
}

void write_frame_images(const std::filesystem::path& out_dir, const std::string& stem, const SphereTraceResult& frame,
                        const SphereTraceSettings& settings) {
  write_colour(out_dir / (stem + ".png"), frame.colour_linear);
  write_step_heatmap(out_dir / (stem + "_steps.png"), frame, settings);
  if (settings.method == TraceMethod::foveated_pyramid) write_image(out_dir / (stem + "_mask.png"), frame.mask);
  if (settings.sampling) write_image(out_dir / (stem + "_samples.png"), samples_per_pixel_image(frame.mask));
}

// What a sweep holds at once, at least: one tracer layout (the largest of its methods: they share
// the tracer, which frees a layout before making the next), and the results of GT, IPR and a FIPR
// frame with the display images the errors compare.
uint64_t bench_memory_bytes(const BenchOptions& options, const BenchPlan& plan) {
  SphereTraceSettings settings = options.settings;
  if (!options.spps.empty())  // the floor keeps a depth a sample
    settings.samples_per_pixel = *std::max_element(options.spps.begin(), options.spps.end());
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
  if (plan.ipr) methods.push_back(settings);
  if (plan.fipr && !plan.variants.empty()) {
    settings.method = TraceMethod::foveated_pyramid;
    settings.foveation = plan.variants.front().foveation;
    methods.push_back(settings);
  }
  for (const SphereTraceSettings& method : methods) {
    layout_bytes = std::max(layout_bytes, render_memory_bytes(method));
    results_bytes += frame_pixels * sizeof(float) * (method.method == TraceMethod::foveated_pyramid ? 5 : 4);
  }
  return layout_bytes + results_bytes + 2 * frame_pixels * 3 * sizeof(float);  // + GT's and a test's display image
}

void run_bench(const BenchOptions& options) {
  const BenchPlan plan = plan_bench(options);
  const std::vector<SceneSource> scenes = load_bench_scenes(options, plan);
  if (!options.out_dir.empty()) create_output_folder(options.out_dir, "--out-dir");

  vk::ContextOptions context_settings = context_options(options.device);
  context_settings.require_gpu = options.require_gpu;
  vk::Context context(context_settings);
  const int width = options.settings.width;
  const int height = options.settings.height;
  std::printf("fovlab bench on %s, %dx%d, %d repeats (median GPU ms); errors against GT at %.1f px/deg, gaze %.1f, "
              "%.1f px\n%s\n%s",
              context.description.name.c_str(), width, height, options.repeats, plan.flip_pixels_per_degree,
              plan.gaze_x_px, plan.gaze_y_px,
              display_line(plan.display, has_display(options.foveation.display) ? ""
                                                                                 : "FIPR's default, a 24-inch display at 600 mm")
                  .c_str(),
              plan.has_cells() ? cell_table_header().c_str() : gt_ipr_table_header().c_str());
  std::fflush(stdout);

  nlohmann::json rows = nlohmann::json::array();
  nlohmann::json cells = nlohmann::json::array();
  const auto print = [&](const std::string& line) {
    std::printf("%s", line.c_str());
    std::fflush(stdout);
  };
  // With --times every cell says its scene time; images of each time are kept apart.
  const bool several_times = plan.times_s.size() > 1;
  float current_time_s = plan.times_s.front();
  const auto add_cell = [&](nlohmann::json cell) {
    cell["time_s"] = current_time_s;
    if (plan.has_cells()) print(cell_table_row(cell));
    cells.push_back(std::move(cell));
  };

  // The sweep's units, (scene, time, spp) in this order; with --cells only the part's.
  const int units_per_scene = int(plan.times_s.size() * options.spps.size());
  const int units = int(scenes.size()) * units_per_scene;
  const std::optional<SweepPart>& part = plan.part;
  const auto held = [&](int unit) { return !part || part->holds(unit); };
  const auto progress = step_progress("bench", part ? part->units_held(units) : units);
  for (size_t scene_index = 0; scene_index < scenes.size(); ++scene_index) {
    const SceneSource& scene = scenes[scene_index];
    const int first_unit = int(scene_index) * units_per_scene;
    bool scene_held = false;
    for (int unit = first_unit; unit < first_unit + units_per_scene; ++unit) scene_held |= held(unit);
    if (!scene_held) continue;
    // One tracer serves every method: a FIPR sequence starts at frame 0 (no history needed), and GT
    // and IPR frames run only between sequences.
    SphereTracer tracer(context, scene);
    for (size_t time_index = 0; time_index < plan.times_s.size(); ++time_index)
    for (size_t spp_index = 0; spp_index < options.spps.size(); ++spp_index) {
      if (!held(first_unit + int(time_index * options.spps.size() + spp_index))) continue;
      const float time_s = plan.times_s[time_index];
      const int spp = options.spps[spp_index];
      current_time_s = time_s;
      SphereTraceSettings gt_settings = options.settings;
      gt_settings.samples_per_pixel = spp;
      gt_settings.time_s = time_s;
      gt_settings.method = TraceMethod::ground_truth;
      SphereTraceSettings ipr_settings = gt_settings;
      ipr_settings.method = TraceMethod::inverted_pyramid;
      SphereTraceSettings floor_settings = gt_settings;
      floor_settings.one_step_floor = true;

      MethodRuns gt;
      MethodRuns ipr;
      MethodRuns floor_runs;
      std::vector<std::pair<SphereTraceSettings, MethodRuns*>> methods{{gt_settings, &gt}, {floor_settings, &floor_runs}};
      if (plan.ipr) methods.emplace_back(ipr_settings, &ipr);
      time_interleaved(tracer, methods, options.repeats);
      const Image gt_image = display_image(gt.frame);
      const double gt_ms = gt.median_gpu_ms();

      nlohmann::json row = {{"scene", scene.name}, {"spp", spp}, {"time_s", time_s}, {"gt", gt.json(gt_settings)},
                            {"floor", floor_runs.json(floor_settings)}};
      row["floor"]["ssim_against_gt"] = frame_errors(gt_image, display_image(floor_runs.frame), plan).ssim;
      row["gt_over_floor"] = gt_ms / floor_runs.median_gpu_ms();
      nlohmann::json cell = gt_cell(scene.name, spp, row["gt"]);
      cell["command"] = cell_command(options, plan, scene.name, time_s, spp, "gt");
      add_cell(cell);
      if (plan.ipr) {
        const FrameErrors errors = frame_errors(gt_image, display_image(ipr.frame), plan);
        row["ipr"] = ipr.json(ipr_settings);
        row["speedup"] = gt_ms / ipr.median_gpu_ms();
        row["ipr_over_floor"] = ipr.median_gpu_ms() / floor_runs.median_gpu_ms();
        row.update(errors.json());
        cell = measured_cell("ipr", scene.name, spp, row["ipr"], gt_ms, errors);
        cell["top_level_share"] = 1.0;
        cell["refreshed_share"] = 0.0;
        cell["command"] = cell_command(options, plan, scene.name, time_s, spp, "ipr");
        add_cell(cell);
      }
      if (!plan.has_cells()) print(gt_ipr_table_row(row));
      rows.push_back(row);
      const std::string stem =
          scene.name + (several_times ? "_t" + format_number(time_s, 6) : std::string()) + "_spp" + std::to_string(spp);
      if (!options.out_dir.empty()) {
        write_frame_images(options.out_dir, stem + "_gt", gt.frame, gt_settings);
        if (plan.ipr) write_frame_images(options.out_dir, stem + "_ipr", ipr.frame, ipr_settings);
      }

      for (const FiprVariant& variant : plan.variants) {
        SphereTraceSettings fipr_settings = gt_settings;
        fipr_settings.method = TraceMethod::foveated_pyramid;
        fipr_settings.foveation = variant.foveation;
        const FiprSequence sequence = time_fipr_sequence(tracer, fipr_settings, options.repeats);
        const SphereTraceResult& frame = sequence.runs.frame;
        const FrameErrors errors = frame_errors(gt_image, display_image(frame), plan);
        cell = measured_cell("fipr", scene.name, spp, sequence.runs.json(fipr_settings), gt_ms, errors);
        const double pixels = double(width) * double(height);
        cell["refresh"] = variant.refresh;
        cell["fovea_deg"] = variant.fovea_deg;
        cell["top_level_share"] = double(frame.foveation.masked_pixels) / pixels;
        cell["refreshed_share"] = double(frame.foveation.refreshed_pixels) / pixels;
        cell["kept_share"] = double(frame.foveation.kept_pixels) / pixels;
        fipr_settings.foveation.frame_index = sequence.last_timed_frame;
        cell["foveation"] = stats_json(scene.name, fipr_settings, frame, 0.0, context)["foveation"];
        cell["warmup_frames"] = sequence.warmup_frames;
        cell["timed_frame_indices"] = {sequence.first_timed_frame, sequence.last_timed_frame};
        cell["measured_frame_index"] = sequence.last_timed_frame;
        cell["command"] = cell_command(options, plan, scene.name, time_s, spp, "fipr", &variant);
        add_cell(cell);
        if (!options.out_dir.empty()) {
          write_frame_images(options.out_dir,
                             stem + "_fipr_r" + std::to_string(variant.refresh) + "_fovea" + variant.fovea_text(),
                             frame, fipr_settings);
        }
      }

      for (const SamplingMap& map : plan.sampling_maps) {
        const std::string name = sampling_model_name(model_of(map));
        SphereTraceSettings model_settings = gt_settings;
        model_settings.method = TraceMethod::sampling_model;
        model_settings.sampling = map;
        model_settings.sampling_filter = plan.sampling.filter;
        MethodRuns runs;
        time_interleaved(tracer, {{model_settings, &runs}}, options.repeats);
        const FrameErrors errors = frame_errors(gt_image, display_image(runs.frame), plan);
        cell = measured_cell(name, scene.name, spp, runs.json(model_settings), gt_ms, errors);
        cell["sampling"] = stats_json(scene.name, model_settings, runs.frame, 0.0, context)["sampling"];
        cell["top_level_share"] = cell["sampling"]["shaded_share"];
        cell["refreshed_share"] = 0.0;
        std::string image_stem = stem + "_" + name;
        if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) {
          cell["focal_share_x"] = rmfr->x.focal_share;
          cell["focal_share_y"] = rmfr->y.focal_share;
          if (plan.focal_shares_x.size() * plan.focal_shares_y.size() > 1)
            image_stem += "_fx" + format_number(rmfr->x.focal_share, 6) + "_fy" + format_number(rmfr->y.focal_share, 6);
        }
        cell["command"] = cell_command(options, plan, scene.name, time_s, spp, name, nullptr, &map);
        add_cell(cell);
        if (!options.out_dir.empty()) write_frame_images(options.out_dir, image_stem, runs.frame, model_settings);
      }
      progress(scene.name + (several_times ? ", t " + format_number(time_s, 6) : std::string()) + ", " +
               std::to_string(spp) + " spp");
    }
  }
  fail_on_validation_messages(context);

  nlohmann::json report = {{"device", context.description.name},
                           {"timestamps", context.timestamp_period_ns > 0},
                           {"width", width},
                           {"height", height},
                           {"repeats", options.repeats},
                           {"pyramid_levels", options.settings.pyramid_levels},
                           {"min_filter_size", options.settings.min_filter_size},
                           {"coarse_test", coarse_test_name(options.settings.coarse_test)},
                           {"full_resolution_depth", options.settings.full_resolution_depth},
                           {"max_steps", options.settings.max_steps},
                           {"hit_threshold", options.settings.hit_threshold},
                           {"time_s", options.settings.time_s},
                           {"times_s", plan.times_s},
                           {"command", sweep_command(options, plan)},
                           {"methods", options.methods},
                           {"camera", "GT and IPR at scene time time_s; a FIPR cell's frames at 60 Hz of scene time "
                                      "ending at time_s (the camera moves), the last compared with GT"},
                           {"metrics",
                            {{"reference", "the GT frame of the same scene and spp"},
                             {"images", "sRGB-encoded display images"},
                             {"flip_pixels_per_degree", plan.flip_pixels_per_degree},
                             {"display", display_json(plan)},
                             {"gaze_px", {plan.gaze_x_px, plan.gaze_y_px}}}},
                           {"rows", rows},
                           {"cells", cells}};
  if (!plan.sampling_maps.empty())
    report["sampling_focal_shares"] = {{"x", plan.focal_shares_x}, {"y", plan.focal_shares_y}};
  if (plan.fipr) {
    report["fipr"] = {
        {"refresh", plan.refreshes},
        {"fovea_deg", plan.fovea_degs},
        {"settings", "every FIPR setting of a cell is in its \"foveation\" object (as fovlab render --stats-json)"},
        {"sequence",
         "per cell: frames 0 to refresh - 1 untimed (frame 0 refreshes every pixel), then --repeats timed frames "
         "continuing the sequence (frame_index increasing, scene time advancing 1/60 s a frame, ending at time_s); "
         "median GPU ms of the timed frames; errors, steps and shares of the last timed frame"},
        {"speedup", "GT median GPU ms of the same scene and spp (timed just before, interleaved with IPR) / FIPR median "
                    "GPU ms"}};
  }
  if (part) {  // a part's Pareto fronts and tables are the whole sweep's, made by bench-merge
    report["part"] = part_json(*part, units);
    write_text_atomically(options.json, report.dump(2) + "\n");
    print("\npart " + std::to_string(part->index) + "/" + std::to_string(part->count) + ": " +
          std::to_string(part->units_held(units)) + " of " + std::to_string(units) +
          " (scene, time, spp) units, written to " + options.json.string() +
          "; fovlab bench-merge joins the parts\n");
    return;
  }
  finish_sweep(report, true, options.json, options.out_dir);
}

}  // namespace

std::vector<SceneSource> load_bench_scenes(const BenchOptions& options, const BenchPlan& plan) {
  check_memory_fits(bench_memory_bytes(options, plan),
                    "--width x --height = " + std::to_string(options.settings.width) + "x" +
                        std::to_string(options.settings.height),
                    "lower --width and --height");
  std::vector<SceneSource> scenes;
  for (const std::string& name : options.scenes) scenes.push_back(load_scene(name));
  return scenes;
}

void add_bench_flags(CLI::App& command, BenchOptions& options) {
  command.add_option("--scenes", options.scenes, "Scenes, comma-separated (names or .glsl paths)")->delimiter(',');
  command.add_option("--spp", options.spps, "Samples per pixel, comma-separated (1, 4, 16)")->delimiter(',');
  command.add_option("--width", options.settings.width, "Frame width in pixels");
  command.add_option("--height", options.settings.height, "Frame height in pixels");
  command.add_option("--repeats", options.repeats, "Timed runs per method and cell (median reported)");
  add_output_option(command, "--json", options.json, "Write the full results as JSON", {{OutputKind::file}, kReplacesAFile});
  add_output_option(command, "--out-dir", options.out_dir,
                    "Write images, step heat maps, FIPR masks, Pareto charts (SVG), table.md and bench.json here", {{OutputKind::folder}, kWritesIntoAFolder});
  command.add_option("--device", options.device, "Vulkan device: index or part of its name (fovlab devices)");
  command.add_flag("--require-gpu", options.require_gpu,
                   "Refuse to run on a CPU Vulkan device (lavapipe): exit 2 on a node without a GPU");
  command.add_option("--cells", options.cells,
                     "I/N: measure only part I of N of the sweep's (scene, time, spp) units, into --json; fovlab "
                     "bench-merge joins the parts into the sweep's report");
  command.add_option("--methods", options.methods,
                     "Methods, comma-separated: gt (always), ipr, fipr, rmfr, hyperbolic, linear, kfr (default gt,ipr)")
      ->delimiter(',');
  add_trace_options(command, options.settings);
  command.add_option("--times", options.times,
                     "Scene times in seconds, comma-separated, instead of --time: every scene is measured at each "
                     "(the rotating patterns turn 10 degrees a second)")
      ->delimiter(',');
  // The FIPR flags of `render`, but a list of refresh periods and of foveae: the sweep.
  add_foveation_flags(command, options.foveation, FoveationPoint::swept);
  command.add_option("--refresh", options.refresh, "FIPR: periphery refresh periods, comma-separated (1, 2, 4)")
      ->delimiter(',');
  command.add_option("--fovea-deg", options.fovea_deg,
                     "FIPR: foveal eccentricities in degrees, comma-separated (default 2.5,5,7.5,10,12.5,15)")
      ->delimiter(',');
  add_sampling_flags(command, options.sampling, false);
  command.add_option("--fx", options.focal_shares_x,
                     "Sampling: rmfr's f_x as shares of the width, comma-separated (with --fy: every pair, Figure 6's "
                     "sweep; default 0.3)")
      ->delimiter(',');
  command.add_option("--fy", options.focal_shares_y, "Sampling: rmfr's f_y as shares of the height, comma-separated")
      ->delimiter(',');
}

void note_given_bench_flags(CLI::App& command, BenchOptions& options) {
  options.fipr_flags_given = given_fipr_only_flags(command);
  options.sampling_flags_given = given_sampling_only_flags(command);
  options.time_given = command.count("--time") > 0;
}

void add_bench_command(CLI::App& app) {
  auto options = std::make_shared<BenchOptions>();
  CLI::App* command =
      app.add_subcommand("bench", "Benchmark GT against IPR, FIPR and the sampling models: time, steps, SSIM, PSNR, FLIP, FPSNR, Pareto fronts");
  add_bench_flags(*command, *options);
  command->callback([options, command] {
    note_given_bench_flags(*command, *options);
    run_bench(*options);
  });
}

}  // namespace fovlab::app
