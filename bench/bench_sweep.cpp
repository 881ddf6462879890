// fovlab bench's measurement: every unit of the plan (or of its part) on one Vulkan device, GT and
// the floor and IPR interleaved, then each FIPR variant as a steady sequence and each sampling
// model's map, every cell's error against the unit's GT frame (bench/bench_runs.h).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench.h"
#include "bench/bench_json.h"
#include "bench/bench_outputs.h"
#include "bench/bench_report.h"
#include "bench/bench_runs.h"
#include "core/colour.h"
#include "core/number_text.h"
#include "renderer/vk/context.h"

namespace fovlab::bench {

namespace {

Image display_image(const SphereTraceResult& frame) { return encode_srgb(frame.colour_linear); }

FrameErrors errors_against(const Image& gt, const SphereTraceResult& frame, const BenchPlan& plan) {
  const BenchOptions& o = plan.options;
  return frame_errors(gt, display_image(frame), o.display, o.gaze_x_px, o.gaze_y_px, plan.flip_pixels_per_degree);
}

CellResult measured_cell(BenchMethod method, const UnitResult& unit, const RunsResult& runs,
                         const FrameErrors& errors) {
  CellResult cell{method, unit.scene, unit.spp, unit.time_s, runs};
  cell.gt_median_gpu_ms = unit.gt.median_gpu_ms;
  cell.speedup = unit.gt.median_gpu_ms / runs.median_gpu_ms;
  cell.errors = errors;
  return cell;
}

}  // namespace

int units_measured(const BenchPlan& plan) {
  return plan.options.part ? plan.options.part->units_held(plan.units()) : plan.units();
}

BenchReport run_bench(const BenchPlan& plan, const std::vector<SceneSource>& scenes,
                      const std::function<void(const std::string& unit)>& progress) {
  const BenchOptions& options = plan.options;
  vk::ContextOptions context_settings{options.device, vk::validation_requested_by_default()};
  context_settings.require_gpu = options.require_gpu;
  vk::Context context(context_settings);
  const int width = options.settings.width;
  const int height = options.settings.height;
  const std::string frame_text = (options.eye_name.empty() ? "" : options.eye_name + " eye ") + std::to_string(width) +
                                 "x" + std::to_string(height);
  std::printf(
      "fovlab bench on %s, %s, %d repeats (median GPU ms); errors against GT at %.1f px/deg, gaze %.1f, "
      "%.1f px\n%s\n%s",
      context.description.name.c_str(), frame_text.c_str(), options.repeats, plan.flip_pixels_per_degree,
      options.gaze_x_px, options.gaze_y_px, options.display_line.c_str(),
      plan.has_cells() ? cell_table_header().c_str() : gt_ipr_table_header().c_str());
  std::fflush(stdout);

  BenchReport report;
  const auto add_cell = [&](CellResult cell) {
    if (plan.has_cells()) print_now(cell_table_row(cell_json(cell)));
    report.cells.push_back(std::move(cell));
  };
  // With --times every cell says its scene time; images of each time are kept apart.
  const bool several_times = plan.times_s.size() > 1;
  const bool write_images = !options.out_dir.empty() && options.write_frame_images;

  // The sweep's units, (scene, time, spp) in this order; with --cells only the part's.
  const int units_per_scene = int(plan.times_s.size() * options.spps.size());
  const std::optional<SweepPart>& part = options.part;
  const auto held = [&](int unit) { return !part || part->holds(unit); };
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
        SphereTraceSettings gt_settings = options.settings;
        gt_settings.samples_per_pixel = spp;
        gt_settings.time_s = time_s;
        gt_settings.method = TraceMethod::ground_truth;
        gt_settings.over_relaxation = 1.0f;  // GT stays the plain reference (--over-relax: IPR's)
        SphereTraceSettings ipr_settings = gt_settings;
        ipr_settings.method = TraceMethod::inverted_pyramid;
        ipr_settings = settings_of(options, ipr_settings);
        ipr_settings.over_relaxation = options.settings.over_relaxation;
        SphereTraceSettings floor_settings = gt_settings;
        floor_settings.one_step_floor = true;

        MethodRuns gt;
        MethodRuns ipr;
        MethodRuns floor_runs;
        std::vector<std::pair<SphereTraceSettings, MethodRuns*>> methods{{gt_settings, &gt},
                                                                         {floor_settings, &floor_runs}};
        if (plan.ipr) methods.emplace_back(ipr_settings, &ipr);
        time_interleaved(tracer, methods, options.repeats);
        const Image gt_image = display_image(gt.frame);
        // The step breakdown: one more untimed frame of each (the same frame, bit for bit).
        const auto step_breakdown_of = [&](SphereTraceSettings settings) {
          settings.step_breakdown = true;
          settings.outputs = TraceOutputs::colour;
          return tracer.render(settings).step_breakdown;
        };
        std::optional<StepBreakdown> gt_steps, ipr_steps;
        if (options.step_breakdown) {
          gt_steps = step_breakdown_of(gt_settings);
          if (plan.ipr) ipr_steps = step_breakdown_of(ipr_settings);
        }

        UnitResult unit{scene.name, spp, time_s, gt.result(gt_settings), floor_runs.result(floor_settings)};
        unit.gt.step_breakdown = gt_steps;
        unit.floor_ssim_against_gt = errors_against(gt_image, floor_runs.frame, plan).ssim;
        unit.gt_over_floor = gt.median_gpu_ms() / floor_runs.median_gpu_ms();
        const std::string stem = scene.name + (several_times ? "_t" + format_number(time_s, 6) : std::string()) +
                                 "_spp" + std::to_string(spp);
        for (const BenchCell& planned : plan.unit_cells) {
          CellResult cell;
          if (planned.method == BenchMethod::gt) {  // the reference: its errors are those of identical frames
            cell = measured_cell(BenchMethod::gt, unit, unit.gt, FrameErrors{});
            cell.speedup = 1.0;
          } else if (planned.method == BenchMethod::ipr) {
            unit.errors = errors_against(gt_image, ipr.frame, plan);
            unit.ipr = ipr.result(ipr_settings);
            unit.ipr->step_breakdown = ipr_steps;
            unit.speedup = gt.median_gpu_ms() / ipr.median_gpu_ms();
            unit.ipr_over_floor = ipr.median_gpu_ms() / floor_runs.median_gpu_ms();
            cell = measured_cell(BenchMethod::ipr, unit, *unit.ipr, unit.errors);
          } else if (planned.method == BenchMethod::fipr) {
            const FiprVariant& variant = plan.variant_of(planned);
            SphereTraceSettings fipr_settings = gt_settings;
            fipr_settings.method = TraceMethod::foveated_pyramid;
            fipr_settings.foveation = variant.foveation;
            fipr_settings = settings_of(options, fipr_settings);
            const FiprSequence sequence = time_fipr_sequence(tracer, fipr_settings, options.repeats);
            const SphereTraceResult& frame = sequence.runs.frame;
            cell = measured_cell(BenchMethod::fipr, unit, sequence.runs.result(fipr_settings),
                                 errors_against(gt_image, frame, plan));
            const double pixels = double(width) * double(height);
            fipr_settings.foveation.frame_index = sequence.last_timed_frame;
            cell.fipr = FiprCellResult{variant.refresh,
                                       variant.fovea_deg,
                                       double(frame.foveation.kept_pixels) / pixels,
                                       fipr_settings.foveation,
                                       frame.foveation,
                                       pixels,
                                       sequence.warmup_frames,
                                       sequence.first_timed_frame,
                                       sequence.last_timed_frame};
            cell.top_level_share = double(frame.foveation.masked_pixels) / pixels;
            cell.refreshed_share = double(frame.foveation.refreshed_pixels) / pixels;
            if (write_images)
              options.write_frame_images(
                  stem + "_fipr_r" + std::to_string(variant.refresh) + "_fovea" + variant.fovea_text(), frame,
                  fipr_settings);
          } else {
            const SamplingMap& map = plan.sampling_of(planned).map;
            SphereTraceSettings model_settings = gt_settings;
            model_settings.method = TraceMethod::sampling_model;
            model_settings.sampling = map;
            model_settings.sampling_filter = options.sampling_filter;
            MethodRuns runs;
            time_interleaved(tracer, {{model_settings, &runs}}, options.repeats);
            cell = measured_cell(planned.method, unit, runs.result(model_settings),
                                 errors_against(gt_image, runs.frame, plan));
            const double pixels = double(width) * double(height);
            SamplingCellResult sampling{model_of(map),
                                        runs.frame.shaded_samples,
                                        double(runs.frame.shaded_samples) / pixels,
                                        theoretical_speedup(map),
                                        pixels / double(std::max<uint64_t>(1, runs.frame.shaded_samples)),
                                        mean_density(map)};
            std::string image_stem = stem + "_" + bench_method_name(planned.method);
            if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) {
              sampling.focal_share_x = rmfr->x.focal_share;
              sampling.focal_share_y = rmfr->y.focal_share;
              if (options.focal_shares_x.size() * options.focal_shares_y.size() > 1)
                image_stem +=
                    "_fx" + format_number(rmfr->x.focal_share, 6) + "_fy" + format_number(rmfr->y.focal_share, 6);
            }
            sampling.reference_sigma = options.sigma;
            sampling.reference_shaded_samples = rmfr_shaded_samples(width, height, options.sigma);
            cell.top_level_share = sampling.shaded_share;
            cell.refreshed_share = 0.0;
            cell.sampling = sampling;
            if (write_images) options.write_frame_images(image_stem, runs.frame, model_settings);
          }
          cell.command = cell_command(plan, scene.name, time_s, spp, planned);
          add_cell(std::move(cell));
          if (planned.method == BenchMethod::ipr || (planned.method == BenchMethod::gt && !plan.ipr)) {
            if (!plan.has_cells()) print_now(gt_ipr_table_row(unit_json(unit)));
            report.rows.push_back(unit);
            if (write_images) {
              options.write_frame_images(stem + "_gt", gt.frame, gt_settings);
              if (plan.ipr) options.write_frame_images(stem + "_ipr", ipr.frame, ipr_settings);
            }
          }
        }
        if (progress)
          progress(scene.name + (several_times ? ", t " + format_number(time_s, 6) : std::string()) + ", " +
                   std::to_string(spp) + " spp");
      }
  }
  if (context.validation_message_count() > 0)
    throw std::runtime_error(std::to_string(context.validation_message_count()) +
                             " Vulkan validation message(s); see above");

  report.device = context.description.name;
  report.timestamps = context.timestamp_period_ns > 0;
  report.settings = options.settings;
  report.min_filter_given = options.pyramid_flags_given.min_filter;
  report.coarse_test_given = options.pyramid_flags_given.coarse_test;
  for (const auto& [run, method] :
       {std::pair{plan.ipr, TraceMethod::inverted_pyramid}, std::pair{plan.fipr, TraceMethod::foveated_pyramid}}) {
    if (!run) continue;
    SphereTraceSettings settings = options.settings;
    settings.method = method;
    settings = settings_of(options, settings);
    report.pyramids.push_back({method == TraceMethod::inverted_pyramid ? BenchMethod::ipr : BenchMethod::fipr,
                               {settings.min_filter_size, settings.coarse_test}});
  }
  report.repeats = options.repeats;
  report.times_s = plan.times_s;
  report.command = sweep_command(plan);
  report.eye_name = options.eye_name;
  report.methods = options.methods;
  report.flip_pixels_per_degree = plan.flip_pixels_per_degree;
  report.display = options.display;
  report.gaze_x_px = options.gaze_x_px;
  report.gaze_y_px = options.gaze_y_px;
  report.fipr = plan.fipr;
  report.refreshes = options.refreshes;
  report.fovea_degs = options.fovea_degs;
  report.sampling = !options.sampling.empty();
  report.focal_shares_x = options.focal_shares_x;
  report.focal_shares_y = options.focal_shares_y;
  report.part = part;
  report.units = plan.units();
  return report;
}

}  // namespace fovlab::bench
