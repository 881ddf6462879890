// fovlab prerender CONFIG [--shard I/N]: renders every path-traced frame a study config's stimuli
// (pt, fpt) show into the pre-render cache, stimuli/cache/<key>/ under the working directory
// (renderer/prerender/frame_cache.h; docs/foveated-path-tracing.md). Frames already there are kept,
// so an interrupted or repeated run renders only what is missing; --shard I/N renders every N-th
// frame of the full list from the I-th (0-based), so N machines can share a study. A progress bar
// with an ETA on a terminal, one line a frame otherwise.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "core/input_error.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

namespace {

struct PrerenderOptions {
  std::string config;
  std::string shard = "0/1";
  std::string device;
  std::string cache = kDefaultCacheRoot.string();
};

struct Shard {
  int index = 0;
  int count = 1;
};

Shard parse_shard(const std::string& text) {
  const auto parts = split_pair(text, "/");
  const auto index = parts ? parse_finite_number(parts->first) : std::nullopt;
  const auto count = parts ? parse_finite_number(parts->second) : std::nullopt;
  if (!index || !count || *count < 1 || *count > 100000 || *index < 0 || *index >= *count ||
      *index != double(int(*index)) || *count != double(int(*count)))
    fail_flag("--shard", "I/N with whole numbers 0 <= I < N (e.g. 0/4: frames 0, 4, 8, ...)", text);
  return {int(*index), int(*count)};
}


void print_progress(bool terminal, int done, int total, double seconds_per_frame, const std::string& file) {
  const double eta_s = seconds_per_frame * (total - done);
  if (!terminal) {
    std::printf("frame %d/%d %.2f s, ETA %s: %s\n", done, total, seconds_per_frame, duration_text(eta_s).c_str(),
                file.c_str());
    std::fflush(stdout);
    return;
  }
  constexpr int kBarWidth = 30;
  const int filled = total > 0 ? done * kBarWidth / total : kBarWidth;
  std::fprintf(stderr, "\r[%s%s] %d/%d frames, %.2f s a frame, ETA %s   ", std::string(size_t(filled), '#').c_str(),
               std::string(size_t(kBarWidth - filled), '.').c_str(), done, total, seconds_per_frame,
               duration_text(eta_s).c_str());
  if (done == total) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

void run_prerender(const PrerenderOptions& options) {
  const Shard shard = parse_shard(options.shard);
  const StudyConfig config = parse_study_config_file(options.config, renderer_scene_catalog());
  const StudyPlan plan = make_study_plan(config, "prerender");  // the stimuli do not depend on the participant
  check_sampling_maps(plan.stimuli, options.config);  // a config no session could run is refused before rendering
  const std::vector<PathTraceFrameJob> all_jobs = path_traced_frame_jobs(planned_specs(plan));
  if (all_jobs.empty())
    throw InputError(options.config + ": no path-traced stimuli (method pt, fpt, pt-rmfr, pt-hyperbolic, pt-linear or pt-kfr); nothing to pre-render");
  std::vector<PathTraceFrameJob> jobs;
  for (size_t i = size_t(shard.index); i < all_jobs.size(); i += size_t(shard.count)) jobs.push_back(all_jobs[i]);

  vk::Context context(context_options(options.device));
  FrameCache cache(context, options.cache);
  std::vector<const PathTraceFrameJob*> missing;
  for (const PathTraceFrameJob& job : jobs)
    if (!cache.has_frame(job.sequence, job.frame)) missing.push_back(&job);
  std::set<std::string> scenes;
  for (const PathTraceFrameJob& job : all_jobs)
    if (scenes.insert(job.sequence.scene).second && !cache.scene_note(job.sequence.scene).empty())
      std::printf("%s: %s\n", job.sequence.scene.c_str(), cache.scene_note(job.sequence.scene).c_str());
  std::printf("%s: %zu frames in all, shard %d/%d holds %zu: %zu cached, %zu to render (cache %s)\n",
              options.config.c_str(), all_jobs.size(), shard.index, shard.count, jobs.size(),
              jobs.size() - missing.size(), missing.size(), kDefaultCacheRoot.c_str());
  std::fflush(stdout);

  const bool terminal = isatty(STDERR_FILENO) != 0;
  const auto started = std::chrono::steady_clock::now();
  uint64_t samples = 0;
  double gpu_ms = 0.0;
  for (size_t i = 0; i < missing.size(); ++i) {
    const PathTraceResult result = cache.render_frame(missing[i]->sequence, missing[i]->frame);
    samples += result.samples;
    gpu_ms += result.gpu_ms;
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    print_progress(terminal, int(i + 1), int(missing.size()), elapsed_s / double(i + 1),
                   cache.frame_file(missing[i]->sequence, missing[i]->frame).string());
  }
  fail_on_validation_messages(context);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!missing.empty())
    std::printf("rendered %zu frames in %s: %.3g samples/s on the GPU clock, %.3g on the wall clock (%s)\n",
                missing.size(), duration_text(wall_s).c_str(), samples_per_second(samples, gpu_ms),
                samples_per_second(samples, 1000.0 * wall_s), context.description.name.c_str());
}

}  // namespace

void add_prerender_command(CLI::App& app) {
  auto options = std::make_shared<PrerenderOptions>();
  CLI::App* command = app.add_subcommand(
      "prerender", "Render a study's path-traced frames into the pre-render cache (stimuli/cache), resuming");
  command->add_option("config", options->config, "Study config (TOML) with pt or fpt stimuli")->required();
  command->add_option("--shard", options->shard, "I/N: render frames I, I + N, I + 2N, ... of the list (default 0/1)");
  command->add_option("--device", options->device, "Vulkan device: index or part of its name (fovlab devices)");
  command->add_option("--cache", options->cache, "Pre-render cache folder (default stimuli/cache under the working directory)");
  command->callback([options] { run_prerender(*options); });
}

}  // namespace fovlab::app
