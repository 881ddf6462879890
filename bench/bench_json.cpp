#include "bench/bench_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "core/atomic_file.h"
#include "core/number_text.h"
#include "foveation/foveation_mask.h"
#include "renderer/sphere_tracing/foveation_json.h"

namespace fovlab::bench {

namespace {

// The top level's step breakdown (renderer/sphere_tracing/step_breakdown.h): per category its steps,
// the samples with a step in it, steps per sample (of all samples) and share of the steps.
nlohmann::json step_breakdown_json(const StepBreakdown& breakdown) {
  const double samples = double(std::max<uint64_t>(1, breakdown.samples));
  const double steps = double(std::max<uint64_t>(1, breakdown.total_steps()));
  nlohmann::json categories = nlohmann::json::object();
  for (int c = 0; c < kStepCategoryCount; ++c) {
    categories[step_category_name(c)] = {{"steps", breakdown.steps[size_t(c)]},
                                         {"samples", breakdown.samples_with[size_t(c)]},
                                         {"steps_per_sample", double(breakdown.steps[size_t(c)]) / samples},
                                         {"share", double(breakdown.steps[size_t(c)]) / steps}};
  }
  nlohmann::json histogram = nlohmann::json::object();
  for (int b = 0; b < kStepHistogramBins; ++b) histogram[step_histogram_bin_name(b)] = breakdown.histogram[size_t(b)];
  return {{"pixels", breakdown.pixels},
          {"samples", breakdown.samples},
          {"total_steps", breakdown.total_steps()},
          {"steps_per_sample", double(breakdown.total_steps()) / samples},
          {"categories", categories},
          {"samples_by_steps", histogram},
          {"one_surface",
           {{"pixels", breakdown.one_surface_pixels},
            {"share", double(breakdown.one_surface_pixels) / double(std::max<uint64_t>(1, breakdown.pixels))},
            {"steps", breakdown.one_surface_steps},
            {"approach_steps", breakdown.one_surface_approach_steps},
            {"longest_approach_steps", breakdown.one_surface_longest_approach},
            {"shared_approach_share",
             double(breakdown.one_surface_approach_steps - breakdown.one_surface_longest_approach) / steps}}}};
}

nlohmann::json runs_json(const RunsResult& runs) {
  nlohmann::json passes = nlohmann::json::object();
  for (const auto& [name, ms] : runs.median_pass_gpu_ms) passes[name] = ms;
  nlohmann::json json = {{"median_gpu_ms", runs.median_gpu_ms},       {"median_wall_ms", runs.median_wall_ms},
                         {"gpu_ms_runs", runs.gpu_ms_runs},           {"median_pass_gpu_ms", passes},
                         {"total_steps", runs.total_steps},           {"steps_per_pixel", runs.steps_per_pixel},
                         {"steps_per_sample", runs.steps_per_sample}, {"capped_rays", runs.capped_rays},
                         {"restarted_rays", runs.restarted_rays}};
  if (runs.step_breakdown) json["step_breakdown"] = step_breakdown_json(*runs.step_breakdown);
  return json;
}

nlohmann::json optional_json(const std::optional<double>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

// ssim, psnr_db, flip, fpsnr_db (null when identical).
nlohmann::json errors_json(const FrameErrors& errors) {
  return {{"ssim", errors.ssim},
          {"psnr_db", optional_json(errors.psnr_db)},
          {"flip", errors.flip},
          {"fpsnr_db", optional_json(errors.fpsnr_db)}};
}

nlohmann::json sampling_json(const SamplingCellResult& sampling) {
  return {{"model", sampling_model_name(sampling.model)},    {"shaded_samples", sampling.shaded_samples},
          {"shaded_share", sampling.shaded_share},           {"theoretical_speedup", sampling.theoretical_speedup},
          {"effective_speedup", sampling.effective_speedup}, {"mean_density", sampling.mean_density},
          {"reference", "rmfr sigma " + format_number(sampling.reference_sigma, 6)},
          {"reference_shaded_samples", sampling.reference_shaded_samples},
          {"shaded_over_reference",
           double(sampling.shaded_samples) / double(std::max<uint64_t>(1, sampling.reference_shaded_samples))}};
}

// --min-filter and --coarse-test as given; a flag not given: each pyramid method's own value
// ({"ipr": 1, "fipr": 3}), or the settings' where neither runs.
nlohmann::json min_filter_json(const BenchReport& report) {
  if (report.min_filter_given || report.pyramids.empty()) return report.settings.min_filter_size;
  nlohmann::json by_method = nlohmann::json::object();
  for (const auto& [method, pyramid] : report.pyramids) by_method[bench_method_name(method)] = pyramid.min_filter_size;
  return by_method;
}
nlohmann::json coarse_test_json(const BenchReport& report) {
  if (report.coarse_test_given || report.pyramids.empty()) return coarse_test_name(report.settings.coarse_test);
  nlohmann::json by_method = nlohmann::json::object();
  for (const auto& [method, pyramid] : report.pyramids)
    by_method[bench_method_name(method)] = coarse_test_name(pyramid.coarse_test);
  return by_method;
}

}  // namespace

nlohmann::json unit_json(const UnitResult& unit) {
  nlohmann::json row = {{"scene", unit.scene},
                        {"spp", unit.spp},
                        {"time_s", unit.time_s},
                        {"gt", runs_json(unit.gt)},
                        {"floor", runs_json(unit.floor)}};
  row["floor"]["ssim_against_gt"] = unit.floor_ssim_against_gt;
  row["gt_over_floor"] = unit.gt_over_floor;
  if (unit.ipr) {
    row["ipr"] = runs_json(*unit.ipr);
    row["speedup"] = unit.speedup;
    row["ipr_over_floor"] = unit.ipr_over_floor;
    row.update(errors_json(unit.errors));
  }
  return row;
}

nlohmann::json cell_json(const CellResult& cell) {
  nlohmann::json json = {{"method", bench_method_name(cell.method)}, {"scene", cell.scene}, {"spp", cell.spp}};
  json.update(runs_json(cell.runs));
  json["gt_median_gpu_ms"] = cell.gt_median_gpu_ms;
  json["speedup"] = cell.speedup;
  json.update(errors_json(cell.errors));
  json["top_level_share"] = cell.top_level_share;
  json["refreshed_share"] = cell.refreshed_share;
  if (cell.fipr) {
    json["refresh"] = cell.fipr->refresh;
    json["fovea_deg"] = cell.fipr->fovea_deg;
    json["kept_share"] = cell.fipr->kept_share;
    json["foveation"] = foveation_json(cell.fipr->foveation, cell.fipr->stats, cell.fipr->pixels);
    json["warmup_frames"] = cell.fipr->warmup_frames;
    json["timed_frame_indices"] = {cell.fipr->first_timed_frame, cell.fipr->last_timed_frame};
    json["measured_frame_index"] = cell.fipr->last_timed_frame;
  }
  if (cell.sampling) {
    json["sampling"] = sampling_json(*cell.sampling);
    if (cell.sampling->focal_share_x) json["focal_share_x"] = *cell.sampling->focal_share_x;
    if (cell.sampling->focal_share_y) json["focal_share_y"] = *cell.sampling->focal_share_y;
  }
  json["command"] = cell.command;
  json["time_s"] = cell.time_s;
  return json;
}

nlohmann::json bench_report_json(const BenchReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const UnitResult& unit : report.rows) rows.push_back(unit_json(unit));
  nlohmann::json cells = nlohmann::json::array();
  for (const CellResult& cell : report.cells) cells.push_back(cell_json(cell));
  nlohmann::json methods = nlohmann::json::array();
  for (BenchMethod method : report.methods) methods.push_back(bench_method_name(method));
  const SphereTraceSettings& s = report.settings;
  nlohmann::json json = {{"device", report.device},
                         {"timestamps", report.timestamps},
                         {"width", s.width},
                         {"height", s.height},
                         {"repeats", report.repeats},
                         {"pyramid_levels", s.pyramid_levels},
                         {"min_filter_size", min_filter_json(report)},
                         {"coarse_test", coarse_test_json(report)},
                         {"full_resolution_depth", s.full_resolution_depth},
                         {"max_steps", s.max_steps},
                         {"hit_threshold", s.hit_threshold},
                         {"time_s", s.time_s},
                         {"times_s", report.times_s},
                         {"command", report.command},
                         {"methods", methods},
                         {"camera",
                          "GT and IPR at scene time time_s; a FIPR cell's frames at 60 Hz of scene time "
                          "ending at time_s (the camera moves), the last compared with GT"},
                         {"metrics",
                          {{"reference", "the GT frame of the same scene and spp"},
                           {"images", "sRGB-encoded display images"},
                           {"flip_pixels_per_degree", report.flip_pixels_per_degree},
                           {"display", display_json(report.display)},
                           {"gaze_px", {report.gaze_x_px, report.gaze_y_px}}}},
                         {"rows", rows},
                         {"cells", cells}};
  if (report.sampling) json["sampling_focal_shares"] = {{"x", report.focal_shares_x}, {"y", report.focal_shares_y}};
  if (report.fipr) {
    json["fipr"] = {
        {"refresh", report.refreshes},
        {"fovea_deg", report.fovea_degs},
        {"settings", "every FIPR setting of a cell is in its \"foveation\" object (as fovlab render --stats-json)"},
        {"sequence",
         "per cell: frames 0 to refresh - 1 untimed (frame 0 refreshes every pixel), then --repeats timed frames "
         "continuing the sequence (frame_index increasing, scene time advancing 1/60 s a frame, ending at time_s); "
         "median GPU ms of the timed frames; errors, steps and shares of the last timed frame"},
        {"speedup",
         "GT median GPU ms of the same scene and spp (timed just before, interleaved with IPR) / FIPR median "
         "GPU ms"}};
  }
  if (s.eye) {  // --headset: which eye, its image's size and its view in the head (metres, degrees)
    const EyeFieldOfView& fov = s.eye->field_of_view;
    const double deg = 180.0 / std::numbers::pi;
    json["eye"] = {
        {"name", report.eye_name},
        {"width_px", s.width},
        {"height_px", s.height},
        {"position_m", s.eye->position_in_head},
        {"orientation", s.eye->orientation_in_head},
        {"fov_deg",
         {fov.angle_left_rad * deg, fov.angle_right_rad * deg, fov.angle_up_rad * deg, fov.angle_down_rad * deg}}};
  }
  if (s.over_relaxation != 1.0f) json["ipr_over_relaxation"] = s.over_relaxation;  // --over-relax
  if (report.part) json["part"] = part_json(*report.part, report.units);
  return json;
}

void write_bench_part(const BenchReport& report, const std::filesystem::path& path) {
  write_text_atomically(path, bench_report_json(report).dump(2) + "\n");
  const SweepPart& part = *report.part;
  std::printf("%s",
              ("\npart " + std::to_string(part.index) + "/" + std::to_string(part.count) + ": " +
               std::to_string(part.units_held(report.units)) + " of " + std::to_string(report.units) +
               " (scene, time, spp) units, written to " + path.string() + "; fovlab bench-merge joins the parts\n")
                  .c_str());
  std::fflush(stdout);
}

}  // namespace fovlab::bench
