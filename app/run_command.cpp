// fovlab run: one participant's session of a study (new, or resumed after the last complete trial).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include <unistd.h>

#include "analysis/statistics/percentile.h"
#include "app/cli_support.h"
#include "app/commands.h"
#include "app/openxr_run.h"
#include "app/output_options.h"
#include "core/input_error.h"
#include "display/window_presenter.h"
#include "protocols/gaze/gaze_spec.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "protocols/session/session.h"

namespace fovlab::app {
namespace {

struct RunOptions {
  std::string config_path;
  SessionOptions session;
  std::string device;
  std::vector<std::string> fields;  // --field NAME=VALUE
};

void run(RunOptions options) {
  const StudyConfig config = parse_study_config_file(options.config_path, renderer_scene_catalog());
  SessionOptions& session = options.session;
  if (!std::isfinite(session.refocus_timeout_s) || session.refocus_timeout_s < 0)
    throw InputError("--refocus-timeout " + std::to_string(session.refocus_timeout_s) +
                     ": expected seconds >= 0 (0: a headset that loses the focus pauses and exits at once)");
  const bool in_headset = config.display.kind == DisplayKind::openxr;
  if (in_headset) {  // the runtime's refusals, before any folder
    if (session.headless)
      throw InputError("--headless: " + config.source_path +
                       " runs in a headset ([display] kind = \"openxr\"); drop --headless (a pilot without one: "
                       "fovlab simulate)");
    // The runtime chooses the GPU the headset's images come from (XR_KHR_vulkan_enable2).
    for (const auto& [flag, value] : {std::pair{"--device", options.device},
                                      std::pair{"--present-device", session.present_device_selector}})
      if (!value.empty())
        throw InputError(std::string(flag) + " " + value + ": " + config.source_path +
                         " runs in a headset, which renders on the GPU its OpenXR runtime chooses; drop " + flag);
    check_openxr_runtime_for(config, session.gaze);
    if (session.mirror_window) check_window_can_open("--mirror-window");
  } else if (session.mirror_window) {
    throw InputError("--mirror-window: " + config.source_path +
                     " runs in a desktop window, which the operator sees already; the mirror is for a headset "
                     "session ([display] kind = \"openxr\"); drop --mirror-window");
  }
  // A gaze-contingent study in a window needs its gaze source named, and a config's [gaze] require
  // is kept (docs/gaze.md): refused before the display is looked for, any window or any folder.
  // A simulated observer without a display runs headless (below). A headset is its own display.
  const bool in_window = !session.headless && (session.observer.empty() || display_available());
  if (!in_headset) choose_gaze(config, session.gaze, !in_window);
  if (!in_headset && !session.headless && !display_available()) {
    if (session.observer.empty())
      throw InputError(
          "run: no display to open a window on (DISPLAY is not set); a human participant needs one "
          "(for a simulated pilot add --observer simulated)");
    session.headless = true;
  }
  if (session.headless && !session.present_device_selector.empty())
    throw InputError("--present-device " + session.present_device_selector +
                     ": a headless session presents nothing; drop it or run with a window");
  const bool participant_was_next = session.participant == "next";
  if (participant_was_next) session.participant = next_participant_id(session.results_dir, config.name);
  const vk::ContextOptions context = context_options(options.device);
  session.device_selector = context.device_selector;
  session.validation = context.validation;
  for (const std::string& field : options.fields) {
    const size_t equals = field.find('=');
    if (equals == std::string::npos || equals == 0)
      throw InputError("--field " + field + ": expected NAME=VALUE (a [participant] field of the config)");
    if (!session.participant_fields.emplace(field.substr(0, equals), field.substr(equals + 1)).second)
      throw InputError("--field " + field.substr(0, equals) + ": given twice; expected each field once");
  }
  // A human at a terminal is asked for the fields the command line left out.
  if (session.observer.empty() && isatty(STDIN_FILENO) == 1)
    session.ask_participant_field = [](const std::string& name) {
      std::fprintf(stderr, "%s: ", name.c_str());
      std::fflush(stderr);
      std::string value;
      if (!std::getline(std::cin, value)) throw InputError("--field " + name + ": no answer on the terminal");
      return value;
    };
  session.prepare_progress = percent_progress("preparing stimuli");
  if (session.headless) session.trial_progress = percent_progress("trials");
  const SessionOutcome outcome = run_session(config, session);
  const char* at_most = outcome.trials_total_is_upper_bound ? "at most " : "";
  std::printf("%s: %s%s%s, %d of %s%d trials complete%s\n", outcome.log_path.c_str(),
              outcome.resumed ? "resumed" : "new session", session.headless ? " (headless, virtual clock)" : "",
              outcome.excluded ? ", participant excluded (attention checks)" : "", outcome.trials_completed, at_most,
              outcome.trials_total,
              outcome.stop_reason.empty() ? "" : (" (stopped: " + outcome.stop_reason + ")").c_str());
  if (!outcome.finished && outcome.trials_completed < outcome.trials_total)
    std::printf("paused after %d of %s%d trials: every answer so far is kept; to resume, run %s\n",
                outcome.trials_completed, at_most, outcome.trials_total,
                participant_was_next ? ("the same command with --participant " + session.participant).c_str()
                                     : "the same command again");
  const int trials_run = std::max(1, outcome.trials_run);
  std::printf(
      "timing: schedule %.2f ms, prepare %.2f s, trial loop %.3f s (%.2f ms a trial), %d events with "
      "%.3f ms write+fsync each, %.2f s in all\n",
      1e3 * outcome.plan_s, outcome.prepare_s, outcome.trial_loop_s, 1e3 * outcome.trial_loop_s / trials_run,
      outcome.events_written, outcome.events_written ? 1e3 * outcome.log_write_s / outcome.events_written : 0.0,
      outcome.wall_s);
  // Gaze-to-present latency of this run's stimulus refreshes (nearest-rank percentiles).
  const analysis::LatencySummary latency = analysis::summarise_latency(outcome.gaze_age_s);
  // A headset's late frames beside the dropped ones, where its runtime lets them be measured.
  const std::string late = outcome.late_frames ? ", " + std::to_string(*outcome.late_frames) + " late" : std::string();
  if (latency.median_ms) {
    std::printf(
        "latency: gaze-to-present median %.2f ms, p95 %.2f ms over %zu refreshes (%s clock), %d dropped frames%s\n",
        *latency.median_ms, *latency.p95_ms, latency.refreshes, outcome.present_clock.c_str(), outcome.dropped_frames,
        late.c_str());
  } else {
    std::printf("latency: no stimulus refresh with a gaze sample in this run, %d dropped frames%s\n",
                outcome.dropped_frames, late.c_str());
  }
  if (outcome.focus_pauses_resumed > 0)
    std::printf("headset: the focus was lost and came back %d time(s); each pause resumed in this run\n",
                outcome.focus_pauses_resumed);
  if (outcome.frame_path == "via_host")
    std::printf(
        "presentation: on another device than the renderer's; %d frames copied through the host, %.3f ms each\n",
        outcome.cross_device_frames,
        outcome.cross_device_frames ? 1e3 * outcome.cross_device_copy_s / outcome.cross_device_frames : 0.0);
}

}  // namespace

void add_run_command(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  CLI::App* command = app.add_subcommand("run", "Run (or resume) a participant's session of a study");
  command->add_option("config", options->config_path, "Study config (TOML)")->required();
  command
      ->add_option("--participant", options->session.participant,
                   "Participant ID (names the log's folder); \"next\": the first unused P001, P002, ...")
      ->required();
  command->add_option("--observer", options->session.observer,
                      "simulated[:threshold=T,slope=S,guess=G,lapse=L,rt=R,seed=N] instead of a person at the keys");
  command->add_flag("--new-version", options->session.new_version,
                    "The config differs from the sessions already in results/<study> (comments and formatting aside): "
                    "run this participant in the folder of its version, results/<study>@v2, @v3, ... (docs/config.md, "
                    "\"Config versions\"), never pooled with the others");
  command->add_flag("--headless", options->session.headless, "No window: a virtual clock (needs --observer)");
  command->add_option(
      "--gaze", options->session.gaze,
      "mouse | trace:FILE | synthetic[:seed=N][,age_ms=A] | "
      "pupil[:HOST[:PORT]][,surface=NAME][,min_confidence=C] | openxr (default: synthetic headless; in a window "
      "the mouse, but a gaze-contingent study needs a tracker named, pupil..., or the mouse by name for a "
      "rehearsal; in a headset its eye tracker, openxr; a config's [gaze] require is kept; the trace format and "
      "the options: docs/gaze.md)");
  CLI::Option* results = add_output_option(
      *command, "--results", options->session.results_dir,
      "Results folder (default: results, and results/simulated for a simulated observer, so that pilots never share a "
      "folder with real participants)",
      {{OutputKind::folder}, "made when missing; a session writes only its own participant's folder in it"});
  command->add_option("--field", options->fields,
                      "NAME=VALUE: a [participant] field of the config (age, handedness, ...); repeat for each. A "
                      "human at a terminal is asked for the others");
  add_output_option(*command, "--cache", options->session.cache_dir,
                    "Pre-render cache of path-traced frames and Voronoi masks (default stimuli/cache under the "
                    "working directory)",
                    {{OutputKind::folder}, kCacheFolder});
  add_output_option(*command, "--screenshots", options->session.screenshots_dir,
                    "Save the first screen of each kind here as PNG, headless too: instructions, fixation, "
                    "stimulus, question, break and break_end, rest and rest_end, end, excluded",
                    {{OutputKind::folder}, kWritesIntoAFolder});
  command->add_option("--device", options->device,
                      "Vulkan device that renders and, in a window, presents: index or part of its name");
  command->add_option("--present-device", options->session.present_device_selector,
                      "Present on another device than --device (e.g. the GPU wired to the monitor of a two-GPU "
                      "laptop): frames are then copied through the host, and the copy is timed");
  command->add_option("--refocus-timeout", options->session.refocus_timeout_s,
                      "Seconds a headset session that lost the focus (headset taken off) waits, paused and sealed, "
                      "for it to come back and resume in this run (default 600; 0: exit at once, and run again to "
                      "resume)");
  command->add_flag("--mirror-window", options->session.mirror_window,
                    "A headset session also opens a window on the desktop for the operator: it shows the left eye's "
                    "image and takes the keyboard (the desktop's answer keys, Escape 3 times to pause and exit) "
                    "beside the controller; closing it closes only the mirror (docs/hmd.md)");
  command->add_option("--lab-key", options->session.lab_key_path,
                      "Key file (16-4096 bytes, kept outside the results folder): seals the log with an HMAC, so "
                      "a changed log cannot be re-sealed without the key");
  command->callback([options, results] {
    if (results->count() == 0 && !options->session.observer.empty()) options->session.results_dir = "results/simulated";
    run(*options);
  });
}

}  // namespace fovlab::app
