#pragma once
// Shared by the session tests: fixture configs, scratch folders, and a summary of a log's complete
// trials that two logs of the same session must agree on (times aside).
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "study/log/session_record.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "tests/support/temp_dir.h"

#include <gtest/gtest.h>

namespace fovlab::test {

inline std::filesystem::path study_fixture(const std::string& name) {
  return std::filesystem::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies" / (name + ".toml");
}

inline std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A log's text as an earlier build would have labelled it: the header's schema_version (this
// build's) replaced by `schema`. The edit breaks the hash chain, which replay also reports.
inline std::string relabelled_schema(std::string log_text, int schema) {
  const std::string today = "\"schema_version\":" + std::to_string(log_schema_version);
  const size_t at = log_text.find(today);
  EXPECT_NE(at, std::string::npos) << "no " << today << " in the log";
  if (at != std::string::npos) log_text.replace(at, today.size(), "\"schema_version\":" + std::to_string(schema));
  return log_text;
}

// A fixture config with some text replaced (still resolved relative to the fixtures folder).
inline StudyConfig fixture_with(const std::string& name, const std::string& from, const std::string& to) {
  const auto path = study_fixture(name);
  std::string text = read_file(path);
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("fixture_with: \"" + from + "\" not in " + name);
  text.replace(at, from.size(), to);
  return parse_study_config_text(text, path.string(), renderer_scene_catalog());
}

// A headless session answered by the simulated observer, with the validation layer on.
inline SessionOptions simulated(const std::filesystem::path& results, const std::string& participant = "P1") {
  SessionOptions options;
  options.participant = participant;
  options.results_dir = results.string();
  options.observer = "simulated";
  options.headless = true;
  options.validation = true;
  return options;
}

// The same, its gaze read from a trace file (time_s,x_px,y_px).
inline SessionOptions simulated_on_trace(const std::filesystem::path& results, const std::filesystem::path& trace) {
  SessionOptions options = simulated(results);
  options.gaze = "trace:" + trace.string();
  return options;
}

// Replay of a log, with the validation layer on.
inline ReplayOutcome replay(const std::string& log_path) {
  ReplayOptions options;
  options.log_path = log_path;
  options.validation = true;
  return replay_session(options);
}

// An empty folder for one session test, removed when the test process exits.
inline std::filesystem::path fresh_folder(const std::string& name) {
  return testing::fresh_scratch_folder("fovlab-session-test-" + name);
}

// One line per complete trial: index, condition, stimuli shown, answers (no times).
inline std::vector<std::string> trial_summary(const std::string& log_path) {
  const SessionRecord record = read_session_record(read_event_log(log_path));
  std::vector<std::string> lines;
  for (const RecordedTrial& trial : record.trials) {
    std::string line = std::to_string(trial.index) + "|" + trial.start.condition + "|";
    for (const StimulusEvent& shown : trial.stimuli) line += std::to_string(shown.stimulus) + ",";
    line += "|";
    for (const ResponseEvent& response : trial.responses) line += response.answer + ",";
    lines.push_back(line);
  }
  return lines;
}

// The log `whole` cut after `cut` bytes (a crash) in a folder of its own, then the session run
// again with `options` (resuming it) there; returns the resumed run and its log path.
inline std::pair<SessionOutcome, std::string> resume_after_cut(const StudyConfig& config, SessionOptions options,
                                                               const std::filesystem::path& results,
                                                               const std::string& whole, size_t cut) {
  const std::filesystem::path folder = results / ("cut" + std::to_string(cut));
  const std::string log_path = session_log_path(folder.string(), config.name, options.participant);
  std::filesystem::create_directories(std::filesystem::path(log_path).parent_path());
  std::ofstream(log_path, std::ios::binary) << whole.substr(0, cut);
  options.results_dir = folder.string();
  return {run_session(config, options), log_path};
}

}  // namespace fovlab::test
