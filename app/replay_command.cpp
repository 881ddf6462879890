// fovlab replay: rebuilds a session from its log and renders its frames again; --verify compares.
#include <cstdio>

#include "app/cli_support.h"
#include "app/commands.h"
#include "app/output_options.h"
#include "protocols/session/replay.h"

namespace fovlab::app {
namespace {

struct ReplayCommandOptions {
  ReplayOptions replay;
  std::string device;
  bool verify = false;
};

void replay(ReplayCommandOptions options) {
  check_output_target(options.replay.cache_dir, "--cache", {OutputKind::folder});  // the default's too
  const vk::ContextOptions context = context_options(options.device);
  options.replay.device_selector = context.device_selector;
  options.replay.validation = context.validation;
  const ReplayOutcome outcome = replay_session(options.replay);
  std::printf("%s: %d trials, %d presented frames compared by %s (%d rendered again%s), render %.2f s of %.2f s\n",
              options.replay.log_path.c_str(), outcome.trials, outcome.presents_checked, outcome.comparison.c_str(),
              outcome.frames_rendered, outcome.same_device ? ", same device" : ", another device", outcome.render_s,
              outcome.wall_s);
  if (outcome.comparison == "ssim") std::printf("lowest SSIM %.6f\n", outcome.lowest_ssim);
  std::printf("log: %s\n", outcome.integrity.describe().c_str());
  if (outcome.difference_count > 0) {
    std::printf("%d difference(s)%s:\n", outcome.difference_count,
                outcome.difference_count > static_cast<int>(outcome.differences.size()) ? ", the first" : "");
    for (const std::string& difference : outcome.differences) std::printf("  %s\n", difference.c_str());
    throw CommandExit{1};
  }
  if (options.verify && !outcome.session_ended) {
    std::printf("the session did not reach its end (interrupted and not resumed): not verified\n");
    throw CommandExit{1};
  }
  if (options.verify && outcome.integrity.status != LogStatus::sealed) {
    std::printf("the log does not end with its seal: not verified\n");
    throw CommandExit{1};
  }
  std::printf("replay matches the log\n");
}

}  // namespace

void add_replay_command(CLI::App& app) {
  auto options = std::make_shared<ReplayCommandOptions>();
  CLI::App* command = app.add_subcommand("replay", "Replay a session from its log (same trials, gaze and frames)");
  command->add_option("log", options->replay.log_path, "A session log (events.jsonl)")->required();
  command->add_flag("--verify", options->verify,
                    "Also require a finished session (any difference always exits with 1)");
  add_output_option(*command, "--frames-out", options->replay.frames_out, "Write every frame rendered again here (PNG)",
                    {{OutputKind::folder}, kWritesIntoAFolder});
  command->add_option("--reference-frames", options->replay.reference_frames,
                      "Compare by SSIM with frames written by --frames-out on the recording device");
  command->add_option("--min-ssim", options->replay.min_ssim, "SSIM a frame must reach with --reference-frames")
      ->check(CLI::Range(0.0, 1.0));
  command->add_option("--device", options->device, "Vulkan device: index or part of its name");
  add_output_option(*command, "--cache", options->replay.cache_dir,
                    "The pre-render cache the session used (default stimuli/cache under the working directory)",
                    {{OutputKind::folder}, kCacheFolder});
  command->add_option("--lab-key", options->replay.lab_key_path,
                      "The lab key the session ran with: verify its seals' MACs");
  command->callback([options] { replay(*options); });
}

}  // namespace fovlab::app
