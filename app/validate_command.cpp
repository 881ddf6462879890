// fovlab validate: checks a study config and prints the schedule it makes (trials, blocks, time).
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "renderer/vk/context.h"
#include "study/config/study_config.h"
#include "study/log/log_estimate.h"
#include "study/schedule/study_plan.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab::app {
namespace {

// Seconds of one call, wall clock.
template <typename Work>
double timed_s(Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  work();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The render time a session spends before its first trial, from a quick timed sample: for each
// (method, scene) of the stimuli rendered ahead, the first stimulus's first, middle and last
// frames (after one untimed frame that compiles the scene), their mean times the group's frames;
// for the stimuli rendered live with the gaze, one frame against the refresh period. Path-traced
// frames come from the pre-render cache and are not timed here (prerender has its own ETA).
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
    Group& group = (describe(spec.method()).depends_on_gaze ? live : ahead)[{std::string(describe(spec.method()).name), spec.scene}];
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
    std::printf("  %-8s %-24s %3d stimuli x %ld frames in all, %.1f ms a frame\n", key.first.c_str(), key.second.c_str(),
                group.stimuli, group.frames, 1e3 * frame_s);
  }
  const double refresh_ms = 1e3 / plan.config.display.refresh_hz;
  for (const auto& [key, group] : live) {
    const StimulusSpec& spec = group.first->spec;
    const int id = next_id++;
    library.prepare({{id, spec}});
    GazeSample centre;
    centre.x_px = 0.5 * spec.width_px;
    centre.y_px = 0.5 * spec.height_px;
    library.frame(id, spec, StimulusImage{0, 0, centre});  // the first frame builds what the rest reuse
    const double frame_s = timed_s([&] { library.frame(id, spec, StimulusImage{0, 1, centre}); });
    std::printf("  %-8s %-24s %3d stimuli rendered live: %.1f ms a frame against a refresh of %.1f ms%s\n",
                key.first.c_str(), key.second.c_str(), group.stimuli, 1e3 * frame_s, refresh_ms,
                1e3 * frame_s > refresh_ms ? " (frames will be dropped on this device)" : "");
  }
  // Path-traced frames: those the pre-render cache lacks render before the first trial too.
  const std::vector<PathTraceFrameJob> jobs = path_traced_frame_jobs(planned_specs(plan));
  FrameCache cache(context, cache_dir);
  size_t missing = 0;
  for (const PathTraceFrameJob& job : jobs) missing += cache.has_frame(job.sequence, job.frame) ? 0 : 1;
  std::printf("render time before the first trial: about %s on %s (timed sample above)%s\n",
              duration_text(ahead_s).c_str(), context.description.name.c_str(),
              jobs.empty() ? ""
                           : (", plus " + std::to_string(missing) + " of " + std::to_string(jobs.size()) +
                              " path-traced frames not yet in " + cache_dir +
                              (missing ? " (fovlab prerender renders them with an ETA)" : ""))
                                 .c_str());
}

void validate(const std::string& config_path, const std::string& participant, bool time_render,
              const std::string& device, const std::string& cache_dir) {
  check_output_target(cache_dir, "--cache", {OutputKind::folder});  // the default's too: the timed sample may fill it
  const StudyConfig config = parse_study_config_file(config_path, renderer_scene_catalog());
  const StudyPlan plan = make_study_plan(config, participant);
  const std::vector<StimulusSpec> specs = planned_specs(plan);
  // A config whose prepared frames would not fit in this machine's memory cannot run here: said now,
  // not after minutes of rendering (the session refuses it the same way).
  check_prepared_frames_fit(specs, config_path);
  check_sampling_maps(plan.stimuli, config_path);
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
  std::printf("display %dx%d at %g Hz, %.1f x %.1f mm at %g mm\n", config.display.width_px, config.display.height_px,
              config.display.refresh_hz, config.display.width_mm, config.display.height_mm,
              config.display.viewing_distance_mm);
  for (const PlannedBlock& block : plan.blocks)
    std::printf("block %-16s scene %-24s %d trials\n", block.name.c_str(), block.scene.c_str(), block.trial_count);
  size_t prepared = 0;  // gaze-dependent stimuli (FIPR) render live and are not held in memory
  for (const PlannedStimulus& stimulus : plan.stimuli) prepared += describe(stimulus.spec.method()).depends_on_gaze ? 0 : 1;
  std::printf("trials %zu (%d attention checks, %d practice), conditions %zu, stimuli %zu x %d frames (%zu prepared ahead: "
              "%.0f MiB; %zu rendered live with the gaze)\n",
              plan.trials.size(), checks, practice, conditions.size(), plan.stimuli.size(), config.stimulus.frame_count(), prepared,
              double(prepared_frames_bytes(specs)) / (1024.0 * 1024.0), plan.stimuli.size() - prepared);
  if (!plan.tracks.empty())
    std::printf("adaptive: %zu track%s (staircases, QUEST+), each planned to its max_trials (one that stops sooner skips "
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
  add_output_option(*command, "--cache", *cache, "Pre-render cache whose path-traced frames count as done (default stimuli/cache)",
                    {{OutputKind::folder}, kCacheFolder});
  command->callback([config_path, participant, no_timing, device, cache] {
    validate(*config_path, *participant, !*no_timing, *device, *cache);
  });
}

}  // namespace fovlab::app
