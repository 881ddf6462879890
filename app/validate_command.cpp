// fovlab validate: checks a study config and prints the schedule it makes (trials, blocks, time).
#include <cstdio>
#include <set>
#include <vector>

#include "app/commands.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab::app {
namespace {

void validate(const std::string& config_path, const std::string& participant) {
  const StudyConfig config = parse_study_config_file(config_path, renderer_scene_catalog());
  const StudyPlan plan = make_study_plan(config, participant);
  const std::vector<StimulusSpec> specs = planned_specs(plan);
  // A config whose prepared frames would not fit in this machine's memory cannot run here: said now,
  // not after minutes of rendering (the session refuses it the same way).
  check_prepared_frames_fit(specs, config_path);
  check_sampling_maps(plan.stimuli, config_path);
  int checks = 0;
  for (const Trial& trial : plan.trials) checks += trial.attention_check ? 1 : 0;
  std::set<std::string> conditions;
  for (const Trial& trial : plan.trials)
    if (!trial.attention_check) conditions.insert(trial.condition);
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
  std::printf("trials %zu (%d attention checks), conditions %zu, stimuli %zu x %d frames (%zu prepared ahead: %.0f MiB; "
              "%zu rendered live with the gaze)\n",
              plan.trials.size(), checks, conditions.size(), plan.stimuli.size(), config.stimulus.frame_count(), prepared,
              double(prepared_frames_bytes(specs)) / (1024.0 * 1024.0), plan.stimuli.size() - prepared);
  std::printf("expected duration %.1f min (1.5 s an answer)\n", minutes);
}

}  // namespace

void add_validate_command(CLI::App& app) {
  auto config_path = std::make_shared<std::string>();
  auto participant = std::make_shared<std::string>("P01");
  CLI::App* command = app.add_subcommand("validate", "Check a study config and print its schedule summary");
  command->add_option("config", *config_path, "Study config (TOML)")->required();
  command->add_option("--participant", *participant, "Participant whose schedule to summarise (default P01)");
  command->callback([config_path, participant] { validate(*config_path, *participant); });
}

}  // namespace fovlab::app
