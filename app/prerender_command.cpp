// fovlab prerender CONFIG [--shard I/N]: renders every path-traced frame a study config's stimuli
// (pt, fpt) show into the pre-render cache, stimuli/cache/<key>/ under the working directory
// (renderer/prerender/frame_cache.h; docs/foveated-path-tracing.md). Frames already there are kept,
// so an interrupted or repeated run renders only what is missing (and what no longer matches its
// .sha256); --shard I/N renders every N-th frame of the full list from the I-th (0-based), so N
// machines can share a study (fovlab slurm prerender, docs/scale-out.md). --verify renders nothing:
// it checks that every frame is there and matches its .sha256, lists those that are not and exits
// 1. A progress bar with an ETA on a terminal, one line a frame otherwise.
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
#include "app/output_options.h"
#include "app/prerender_jobs.h"
#include "core/input_error.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"
#include "protocols/stimuli/plan_renderable.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

namespace {

using Shard = PartOfN;

struct PrerenderOptions {
  std::string config;
  std::string shard = "0/1";
  std::string device;
  std::string cache = kDefaultCacheRoot.string();
  bool verify = false;
  bool require_gpu = false;
};

Shard parse_shard(const std::string& text) { return parse_part_of_n(text, "--shard", "e.g. 0/4: frames 0, 4, 8, ..."); }

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

}  // namespace

std::vector<PathTraceFrameJob> prerender_frame_jobs(const std::string& config_path) {
  const StudyConfig config = parse_study_config_file(config_path, renderer_scene_catalog());
  const StudyPlan plan = make_study_plan(config, "prerender");  // the stimuli do not depend on the participant
  check_plan_renderable(plan, config_path,
                        PlanUse::prerender);  // a config no session could run is refused before rendering
  std::vector<PathTraceFrameJob> jobs = path_traced_frame_jobs(planned_specs(plan), study_frame_views(config.display));
  if (jobs.empty())
    throw InputError(config_path +
                     ": no path-traced stimuli (method pt, fpt, pt-rmfr, pt-hyperbolic, pt-linear or pt-kfr); nothing "
                     "to pre-render");
  return jobs;
}

namespace {

// --verify: every frame of the shard whole and matching its .sha256; the others listed, one line
// each, and exit code 1. Needs no Vulkan device.
void verify_frames(const PrerenderOptions& options, const Shard& shard, const std::vector<PathTraceFrameJob>& jobs,
                   size_t all_frames) {
  FrameCache cache(options.cache);
  size_t bad = 0;
  std::set<std::string> sequences;
  for (const PathTraceFrameJob& job : jobs) {
    sequences.insert(job.sequence.description());
    const FrameStatus status = cache.frame_status(job.sequence, job.frame);
    if (status == FrameStatus::whole) continue;
    ++bad;
    std::printf("%s: %s\n", cache.frame_file(job.sequence, job.frame).c_str(), frame_status_text(status));
  }
  std::printf(
      "%s: %zu frames in all, shard %d/%d holds %zu in %zu sequences: %zu whole and matching their .sha256, "
      "%zu not (cache %s)\n",
      options.config.c_str(), all_frames, shard.index, shard.count, jobs.size(), sequences.size(), jobs.size() - bad,
      bad, options.cache.c_str());
  std::fflush(stdout);
  if (bad > 0) throw CommandExit{1};
}

void run_prerender(const PrerenderOptions& options) {
  check_output_target(options.cache, "--cache", {OutputKind::folder});  // the default's too
  const Shard shard = parse_shard(options.shard);
  const std::vector<PathTraceFrameJob> all_jobs = prerender_frame_jobs(options.config);
  std::vector<PathTraceFrameJob> jobs;
  for (size_t i = size_t(shard.index); i < all_jobs.size(); i += size_t(shard.count)) jobs.push_back(all_jobs[i]);
  if (options.verify) return verify_frames(options, shard, jobs, all_jobs.size());

  vk::ContextOptions context_settings = context_options(options.device);
  context_settings.require_gpu = options.require_gpu;
  vk::Context context(context_settings);
  FrameCache cache(context, options.cache);
  std::vector<const PathTraceFrameJob*> missing;
  size_t altered = 0;
  size_t unhashed = 0;
  for (const PathTraceFrameJob& job : jobs) {
    const FrameStatus status = cache.frame_status(job.sequence, job.frame);
    if (status == FrameStatus::whole) continue;
    altered += status == FrameStatus::altered;
    unhashed += status == FrameStatus::unhashed;  // nothing says it is the frame rendered: rendered again
    missing.push_back(&job);
  }
  std::set<std::string> scenes;
  for (const PathTraceFrameJob& job : all_jobs)
    if (scenes.insert(job.sequence.scene).second && !cache.scene_note(job.sequence.scene).empty())
      std::printf("%s: %s\n", job.sequence.scene.c_str(), cache.scene_note(job.sequence.scene).c_str());
  std::printf("%s: %zu frames in all, shard %d/%d holds %zu: %zu cached, %zu to render (cache %s)\n",
              options.config.c_str(), all_jobs.size(), shard.index, shard.count, jobs.size(),
              jobs.size() - missing.size(), missing.size(), options.cache.c_str());
  if (unhashed > 0)
    std::printf(
        "%zu frames had no .sha256 beside them (left so by an older fovlab, or replaced and their hash "
        "deleted): rendered again\n",
        unhashed);
  if (altered > 0) std::printf("%zu frames differ from their .sha256: rendered again\n", altered);
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
  add_output_option(*command, "--cache", options->cache,
                    "Pre-render cache folder (default stimuli/cache under the working directory)",
                    {{OutputKind::folder}, kCacheFolder});
  command->add_flag("--verify", options->verify,
                    "Render nothing: check that every frame (of the shard) is there and matches its .sha256; list "
                    "those that do not and exit 1");
  command->add_flag("--require-gpu", options->require_gpu,
                    "Refuse to render on a CPU Vulkan device (lavapipe): exit 2 on a node without a GPU");
  command->callback([options] { run_prerender(*options); });
}

}  // namespace fovlab::app
