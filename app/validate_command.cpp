// fovlab validate: checks a study config and prints the schedule it makes (trials, blocks, time).
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "core/number_text.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/vk/context.h"
#include "study/config/study_config.h"
#include "study/log/log_estimate.h"
#include "study/schedule/study_plan.h"
#include "protocols/stimuli/plan_renderable.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab::app {
namespace {

namespace fs = std::filesystem;

// Seconds of one call, wall clock.
template <typename Work>
double timed_s(Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// What pre-rendering the path-traced frames not yet cached costs, from a short timed render: of each
// scene's missing frames the first is rendered (and stored: the cache keeps it, so prerender and
// the session skip it), timed on the wall clock and measured on disk (the frame and its .sha256);
// the scene's other missing frames are scaled from it by their samples (width x height x samples
// per pixel) for the time and by their pixels for the disk.
// "3.2 MiB", "1.5 GiB", "812 KiB": an estimate's size, in binary units.
std::string approximate_size_text(double bytes) {
  const char* const units[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 4) {
    bytes /= 1024.0;
    ++unit;
  }
  char text[32];
  std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.1f %s", bytes, units[unit]);
  return text;
}

struct PrerenderEstimate {
  double seconds = 0.0;
  uint64_t bytes = 0;
};

PrerenderEstimate estimate_prerender(FrameCache& cache, const std::vector<const PathTraceFrameJob*>& missing) {
  std::map<std::string, std::vector<const PathTraceFrameJob*>> by_scene;
  for (const PathTraceFrameJob* job : missing) by_scene[job->sequence.scene].push_back(job);
  const auto samples_of = [](const PathTraceSequence& sequence) {
    return double(sequence.width_px) * double(sequence.height_px) * double(sequence.samples_per_pixel);
  };
  const auto pixels_of = [](const PathTraceSequence& sequence) {
    return double(sequence.width_px) * double(sequence.height_px);
  };
  PrerenderEstimate total;
  for (const auto& [scene, jobs] : by_scene) {
    const PathTraceFrameJob& timed = *jobs.front();
    const double frame_s = timed_s([&] { cache.render_frame(timed.sequence, timed.frame); });
    std::error_code error;
    const uintmax_t frame_bytes = fs::file_size(cache.frame_file(timed.sequence, timed.frame), error);
    const uintmax_t hash_bytes = fs::file_size(cache.hash_file(timed.sequence, timed.frame), error);
    const double bytes_per_pixel = double(error ? 0 : frame_bytes + hash_bytes) / pixels_of(timed.sequence);
    const double seconds_per_sample = frame_s / samples_of(timed.sequence);
    double scene_s = frame_s, scene_bytes = bytes_per_pixel * pixels_of(timed.sequence);
    for (size_t i = 1; i < jobs.size(); ++i) {
      scene_s += seconds_per_sample * samples_of(jobs[i]->sequence);
      scene_bytes += bytes_per_pixel * pixels_of(jobs[i]->sequence);
    }
    std::printf(
        "  %-8s %-24s %zu path-traced frames not yet cached: about %s and %s on disk (one rendered and "
        "cached: %.2f s, %s)\n",
        "pt", scene.c_str(), jobs.size(), duration_text(scene_s).c_str(), approximate_size_text(scene_bytes).c_str(),
        frame_s, approximate_size_text(bytes_per_pixel * pixels_of(timed.sequence)).c_str());
    total.seconds += scene_s;
    total.bytes += static_cast<uint64_t>(scene_bytes);
  }
  return total;
}

// The render time a session spends before its first trial, from a quick timed sample: for each
// (method, scene) of the stimuli rendered ahead, the first stimulus's first, middle and last
// frames (after one untimed frame that compiles the scene), their mean times the group's frames;
// for the stimuli rendered live with the gaze, one frame against the refresh period. Path-traced
// frames come from the pre-render cache: those it lacks are estimated by estimate_prerender.
void estimate_render_time(const StudyPlan& plan, const std::string& device, const std::string& cache_dir) {
  std::unique_ptr<vk::Context> made;
  try {
    made = std::make_unique<vk::Context>(context_options(device));
  } catch (const std::exception& error) {  // validate checks a config on any machine: the timing is extra
    std::printf("render time: not estimated (%s)\n", error.what());
    return;
  }
  vk::Context& context = *made;
  StimulusLibrary library(context, cache_dir);
  struct Group {
    const PlannedStimulus* first = nullptr;
    int stimuli = 0;
    long frames = 0;
  };
  std::map<std::pair<std::string, std::string>, Group> ahead, live;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    const StimulusSpec& spec = stimulus.spec;
    if (is_path_traced(spec.method())) continue;
    Group& group =
        (describe(spec.method()).depends_on_gaze ? live
                                                 : ahead)[{std::string(describe(spec.method()).name), spec.scene}];
    if (!group.first) group.first = &stimulus;
    ++group.stimuli;
    group.frames += spec.frame_count;
  }
  int next_id = 0;
  double ahead_s = 0.0;
  for (const auto& [key, group] : ahead) {
    const StimulusSpec& spec = group.first->spec;
    StimulusSpec one = spec;
    one.frame_count = 1;
    library.prepare({{next_id++, one}});  // compiles the scene: not timed
    double sum_s = 0.0;
    const int samples[] = {0, spec.frame_count / 2, spec.frame_count - 1};
    for (int frame : samples) {
      one.camera_start_s = spec.frame_time_s(frame);  // that frame's camera, as frame 0 of a copy
      sum_s += timed_s([&] { library.prepare({{next_id++, one}}); });
    }
    const double frame_s = sum_s / 3.0;
    ahead_s += frame_s * double(group.frames);
    std::printf("  %-8s %-24s %3d stimuli x %ld frames in all, %.1f ms a frame\n", key.first.c_str(),
                key.second.c_str(), group.stimuli, group.frames, 1e3 * frame_s);
  }
  const double refresh_ms = 1e3 / plan.config.display.refresh_hz;
  const int eyes = plan.config.display.kind == DisplayKind::openxr ? 2 : 1;  // a headset renders both a refresh
  for (const auto& [key, group] : live) {
    const StimulusSpec& spec = group.first->spec;
    const int id = next_id++;
    library.prepare({{id, spec}});
    GazeSample centre;
    centre.x_px = 0.5 * spec.width_px;
    centre.y_px = 0.5 * spec.height_px;
    library.frame(id, spec, StimulusImage{0, 0, centre});  // image 0: the timed image 1 continues it
    const double frame_s = timed_s([&] { library.frame(id, spec, StimulusImage{0, 1, centre}); });
    ahead_s += frame_s * double(group.stimuli);  // prepare renders one image of each, unseen
    std::printf("  %-8s %-24s %3d stimuli rendered live: %.1f ms a frame%s against a refresh of %.1f ms%s\n",
                key.first.c_str(), key.second.c_str(), group.stimuli, 1e3 * frame_s,
                eyes == 2 ? " (an eye: two a refresh)" : "", refresh_ms,
                eyes * 1e3 * frame_s > refresh_ms ? " (frames will be dropped on this device)" : "");
  }
  // Path-traced frames: those the pre-render cache lacks render before the first trial too.
  const std::vector<PathTraceFrameJob> jobs =
      path_traced_frame_jobs(planned_specs(plan), study_frame_views(plan.config.display));
  FrameCache cache(context, cache_dir);
  std::vector<const PathTraceFrameJob*> missing;
  for (const PathTraceFrameJob& job : jobs)
    if (!cache.has_frame(job.sequence, job.frame)) missing.push_back(&job);
  const PrerenderEstimate prerender = estimate_prerender(cache, missing);
  std::string path_traced;
  if (!jobs.empty() && missing.empty())
    path_traced = ", all " + std::to_string(jobs.size()) + " path-traced frames already in " + cache_dir;
  else if (!jobs.empty())
    path_traced = ", including the pre-render of " + std::to_string(missing.size()) + " of " +
                  std::to_string(jobs.size()) + " path-traced frames not yet in " + cache_dir + ": about " +
                  duration_text(prerender.seconds) + " and " + approximate_size_text(double(prerender.bytes)) +
                  " on disk (fovlab prerender renders them ahead, with an ETA)";
  std::printf("render time before the first trial: about %s on %s (timed sample above)%s\n",
              duration_text(ahead_s + prerender.seconds).c_str(), context.description.name.c_str(),
              path_traced.c_str());
}

// A headset's plan is made for its left eye's image; the right eye's is checked too where its field
// of view has another size (the sampling maps' checks depend on it).
void check_right_eye_renderable(const StudyConfig& config, const std::string& participant,
                                const std::string& config_path) {
  if (config.display.kind != DisplayKind::openxr) return;
  const FlatDisplayOfEye right = flat_display_of_eye(config.display.headset.right_eye_fov);
  if (right.width_mm == config.display.width_mm && right.height_mm == config.display.height_mm) return;
  StudyConfig right_eye = config;
  right_eye.display.width_mm = right.width_mm;
  right_eye.display.height_mm = right.height_mm;
  right_eye.display.viewing_distance_mm = right.viewing_distance_mm;
  check_plan_renderable(make_study_plan(right_eye, participant), config_path + " (right eye)", PlanUse::session);
}

// The headset's display: one line for the whole, then one an eye (its angles, angular size and
// pixels per degree at the view's centre).
void print_headset_display(const DisplayConfig& display) {
  const HeadsetDisplayConfig& headset = display.headset;
  std::printf("display openxr: %dx%d px an eye at %g Hz, %s, gaze to each eye through %s, IPD %g mm\n",
              headset.eye_width_px, headset.eye_height_px, display.refresh_hz,
              headset_view_model_name(headset.view_model),
              headset.gaze_fixation == GazeFixation::rendered_depth
                  ? "the rendered depth"
                  : ("a point " + format_number(headset.fixation_distance_mm, 6) + " mm along the ray").c_str(),
              headset.ipd_mm);
  for (const auto& [name, fov] :
       {std::pair{"left ", headset.left_eye_fov}, std::pair{"right", headset.right_eye_fov}}) {
    const EyeViewGeometry eye = eye_view_geometry(fov, headset.eye_width_px, headset.eye_height_px);
    std::printf("  %s eye %s: %.1f x %.1f deg, %.2f x %.2f px/deg at the view's centre (pixel %.1f, %.1f)\n", name,
                field_of_view_text(fov).c_str(), eye.width_deg, eye.height_deg, eye.pixels_per_degree_x,
                eye.pixels_per_degree_y, eye.centre_x_px, eye.centre_y_px);
  }
}

void validate(const std::string& config_path, const std::string& participant, bool time_render,
              const std::string& device, const std::string& cache_dir) {
  check_output_target(cache_dir, "--cache", {OutputKind::folder});  // the default's too: the timed sample may fill it
  const StudyConfig config = parse_study_config_file(config_path, renderer_scene_catalog());
  const StudyPlan plan = make_study_plan(config, participant);
  check_plan_renderable(plan, config_path, PlanUse::session);  // what a session would refuse, refused now
  check_right_eye_renderable(config, participant, config_path);
  check_log_fits_readers(plan, config_path);  // what validate accepts, the log readers can read back
  int checks = 0, practice = 0;
  std::set<std::string> conditions;
  for (const Trial& trial : plan.trials) {
    checks += trial.attention_check ? 1 : 0;
    practice += trial.practice ? 1 : 0;
    if (!trial.attention_check && !trial.practice) conditions.insert(trial.condition);
  }
  const double minutes = plan.expected_duration_s() / 60.0;
  std::printf("%s: valid\n", config_path.c_str());
  std::printf("study %s, protocol %s, seed %llu; participant \"%s\" (session seed %llu)\n", config.name.c_str(),
              protocol_name(config.protocol.kind), static_cast<unsigned long long>(config.seed), participant.c_str(),
              static_cast<unsigned long long>(plan.session_seed));
  if (config.display.kind == DisplayKind::openxr) print_headset_display(config.display);
  else
    std::printf("display %dx%d at %g Hz, %.1f x %.1f mm at %g mm\n", config.display.width_px, config.display.height_px,
                config.display.refresh_hz, config.display.width_mm, config.display.height_mm,
                config.display.viewing_distance_mm);
  // Which gaze sources may run it (docs/gaze.md, "Which source a session may use").
  if (!config.gaze.require.empty())
    std::printf("gaze: [gaze] require = %s (a source of another kind is refused, headless too)\n",
                config.gaze.require_text().c_str());
  else if (is_gaze_contingent(config) && config.display.kind == DisplayKind::openxr)
    std::printf(
        "gaze: gaze-contingent: a headset session takes the headset's eye gaze (XR_EXT_eye_gaze_interaction); on a "
        "runtime without it, a trace or synthetic source the config names ([gaze] require)\n");
  else if (is_gaze_contingent(config))
    std::printf(
        "gaze: gaze-contingent: a session in a window needs --gaze (a tracker: pupil[:HOST[:PORT]]; --gaze mouse "
        "for a rehearsal); headless: synthetic\n");
  for (const PlannedBlock& block : plan.blocks)
    std::printf("block %-16s scene %-24s %d trials\n", block.name.c_str(), block.scene.c_str(), block.trial_count);
  size_t prepared = 0;  // gaze-dependent stimuli (FIPR) render live and are not held in memory
  for (const PlannedStimulus& stimulus : plan.stimuli)
    prepared += describe(stimulus.spec.method()).depends_on_gaze ? 0 : 1;
  std::printf(
      "trials %zu (%d attention checks, %d practice), conditions %zu, stimuli %zu x %d frames (%zu prepared ahead: "
      "%.0f MiB; %zu rendered live with the gaze)\n",
      plan.trials.size(), checks, practice, conditions.size(), plan.stimuli.size(), config.stimulus.frame_count(),
      prepared, double(prepared_frames_bytes(planned_specs(plan))) / (1024.0 * 1024.0), plan.stimuli.size() - prepared);
  if (!plan.tracks.empty())
    std::printf(
        "adaptive: %zu track%s (staircases, QUEST+), each planned to its max_trials (one that stops sooner skips "
        "the rest: the trials and duration are upper bounds)\n",
        plan.tracks.size(), plan.tracks.size() == 1 ? "" : "s");
  std::printf("expected duration %.1f min of trials (1.5 s an answer%s)\n", minutes,
              config.validation.enabled ? ", eye-tracker validations passing at once" : "");
  if (time_render) estimate_render_time(plan, device, cache_dir);
}

}  // namespace

void add_validate_command(CLI::App& app) {
  auto config_path = std::make_shared<std::string>();
  auto participant = std::make_shared<std::string>("P01");
  CLI::App* command = app.add_subcommand("validate", "Check a study config and print its schedule summary");
  command->add_option("config", *config_path, "Study config (TOML)")->required();
  command->add_option("--participant", *participant, "Participant whose schedule to summarise (default P01)");
  auto no_timing = std::make_shared<bool>(false);
  auto device = std::make_shared<std::string>();
  command->add_flag("--no-render-timing", *no_timing,
                    "Skip the quick timed sample that estimates the render time before the first trial");
  command->add_option("--device", *device, "Vulkan device of the timed sample: index or part of its name");
  auto cache = std::make_shared<std::string>(kDefaultCacheRoot.string());
  add_output_option(*command, "--cache", *cache,
                    "Pre-render cache whose path-traced frames count as done (default stimuli/cache)",
                    {{OutputKind::folder}, kCacheFolder});
  command->callback([config_path, participant, no_timing, device, cache] {
    validate(*config_path, *participant, !*no_timing, *device, *cache);
  });
}

}  // namespace fovlab::app
