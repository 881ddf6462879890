// study/log/session_scan.h must tell the same story as read_session_record (the reader resume
// and replay use), on logs with every kind of trial event, a resume that drops a cut-off trial, a
// torn tail, an edited line and lines it must reject.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>

#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "study/log/session_scan.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

using nlohmann::json;

std::string scratch_log(const std::string& name) {
  const auto path = testing::scratch_folder("fovlab-scan-test") / name;
  std::filesystem::remove(path);
  return path.string();
}

// A log with a ramp-like trial (several answers), an attention check answered wrongly, a slider
// save, a trial cut off by a crash and run again after session_resumed, and gaze arrays to skip.
std::string write_rich_log(const std::string& name) {
  const std::string path = scratch_log(name);
  EventLogWriter log(path, "", 0);
  log.append({{"event", "session_header"},
              {"schema_version", log_schema_version},
              {"study", "s"},
              {"participant", "p"},
              {"t", 0.0},
              {"config_toml", "text with \"chain\":\"" + std::string(64, '0') + "\" inside"}});
  log.append({{"event", "block_start"}, {"block", 0}, {"name", "courtyard"}, {"scene", "x.glsl"}, {"t", 0.1}});
  log.append({{"event", "block_start"}, {"block", 1}, {"name", ""}, {"scene", "temple"}, {"t", 0.1}});
  log.append({{"event", "trial_start"},
              {"trial", 0},
              {"block", 0},
              {"condition", "blur/level=7.5"},
              {"variant", "blur"},
              {"level", 7.5},
              {"attention_check", false},
              {"sequence", {3, 0}},
              {"reference_first", false},
              {"t", 1.0}});
  log.append({{"event", "stimulus"},
              {"trial", 0},
              {"step", 0},
              {"gaze", {{1.5, 2.5}, {3.0, 4.0}}},
              {"frame", {0, 1}},
              {"hash", {"ab", "cd"}},
              {"t", 1.1}});
  log.append(
      {{"event", "response"}, {"trial", 0}, {"step", 1}, {"answer", "same"}, {"key", "s"}, {"rt_s", 0.4}, {"t", 1.2}});
  log.append({{"event", "trial_end"}, {"trial", 0}, {"t", 1.3}});
  log.append({{"event", "trial_start"},
              {"trial", 1},
              {"block", 1},
              {"condition", "attention_check"},
              {"variant", ""},
              {"attention_check", true},
              {"sequence", {0, 0}},
              {"reference_first", true},
              {"t", 2.0}});
  log.append({{"event", "response"}, {"trial", 1}, {"step", 1}, {"answer", "different"}, {"t", 2.1}});
  log.append({{"event", "attention_check"}, {"trial", 1}, {"correct", false}, {"errors", 1}, {"t", 2.1}});
  log.append({{"event", "break"}, {"trial", 1}, {"reason", "attention_check"}, {"t", 2.2}});
  log.append({{"event", "trial_end"}, {"trial", 1}, {"t", 3.0}});
  log.append({{"event", "trial_start"},
              {"trial", 2},
              {"block", 1},
              {"condition", "slider"},
              {"variant", ""},
              {"attention_check", false},
              {"sequence", {1, 2, 3}},
              {"slider_start", 0},
              {"t", 4.0}});
  log.append({{"event", "response"}, {"trial", 2}, {"step", 0}, {"answer", "up"}, {"t", 4.1}});
  log.append({{"event", "session_resumed"}, {"next_trial", 2}, {"t", 5.0}});  // the crash cut trial 2
  log.append({{"event", "trial_start"},
              {"trial", 2},
              {"block", 1},
              {"condition", "slider"},
              {"variant", ""},
              {"attention_check", false},
              {"sequence", {1, 2, 3}},
              {"slider_start", 0},
              {"t", 6.0}});
  log.append({{"event", "response"}, {"trial", 2}, {"step", 0}, {"answer", "reference"}, {"t", 6.1}});
  log.append({{"event", "response"}, {"trial", 2}, {"step", 1}, {"answer", "save"}, {"t", 6.2}});
  log.append(
      {{"event", "slider_saved"}, {"trial", 2}, {"ladder_index", 1}, {"stimulus", 2}, {"level", 15}, {"t", 6.2}});
  log.append({{"event", "trial_end"}, {"trial", 2}, {"t", 6.3}});
  log.append({{"event", "trial_start"},
              {"trial", 3},
              {"block", 1},
              {"condition", "level=5"},
              {"variant", ""},
              {"level", 5},
              {"attention_check", false},
              {"sequence", {0, 1}},
              {"t", 7.0}});
  log.append({{"event", "excluded"}, {"errors", 3}, {"max_errors", 3}, {"t", 7.5}});
  log.append({{"event", "session_end"}, {"reason", "excluded"}, {"completed_trials", 3}, {"t", 7.6}});
  return path;
}

void expect_same_story(const std::string& path) {
  const EventLogFile log = read_event_log(path);
  const SessionRecord record = read_session_record(log);
  const ScannedSession scan = scan_session_log(path);
  EXPECT_EQ(scan.header, record.header);
  EXPECT_EQ(scan.first_chain_error_line, log.first_chain_error_line);
  EXPECT_EQ(scan.torn_tail_bytes, log.torn_tail ? log.torn_tail->size() : 0u);
  EXPECT_EQ(scan.excluded, record.excluded);
  EXPECT_EQ(scan.ended, record.ended);
  EXPECT_EQ(scan.attention_errors, record.attention_errors);
  EXPECT_EQ(scan.incomplete_trial, record.incomplete_trial);
  ASSERT_EQ(scan.trials.size(), record.trials.size());
  for (size_t i = 0; i < scan.trials.size(); ++i) {
    const ScannedTrial& fast = scan.trials[i];
    const RecordedTrial& full = record.trials[i];
    EXPECT_EQ(fast.index, full.index);
    EXPECT_EQ(fast.block, full.start.block);
    EXPECT_EQ(fast.condition, full.start.condition);
    EXPECT_EQ(fast.variant, full.start.variant);
    EXPECT_EQ(fast.level, full.start.level);
    EXPECT_EQ(fast.attention_check, full.start.attention_check);
    EXPECT_EQ(fast.reference_first, full.start.reference_first);
    EXPECT_EQ(fast.sequence, full.start.sequence);
    ASSERT_EQ(fast.answers.size(), full.responses.size());
    for (size_t j = 0; j < fast.answers.size(); ++j) {
      EXPECT_EQ(fast.answers[j], full.responses[j].answer);
      EXPECT_EQ(fast.answer_steps[j], full.responses[j].step);
    }
    EXPECT_EQ(fast.ramp_toward_reference, full.start.ramp_toward_reference.value_or(true));
    EXPECT_EQ(fast.attention_correct.has_value(), full.attention_check.has_value());
    if (fast.attention_correct) {
      EXPECT_EQ(*fast.attention_correct, full.attention_check->correct.value_or(true));
    }
    std::optional<double> saved;
    for (const SliderSavedEvent& event : full.slider_saved) saved = event.level;
    EXPECT_EQ(fast.saved_level, saved);
    EXPECT_EQ(fast.practice, full.start.practice);
    EXPECT_EQ(fast.track, full.start.track);
    // The stimulus events' fields the scan keeps (log_event_fields.h: typed and kept rows).
    int64_t dropped_frames = 0, gaze_refreshes = 0, gaze_off_image = 0, gaze_invalid_other = 0;
    int stimuli_with_latency = 0;
    std::vector<double> gaze_age_s, frame_interval_s;
    for (const StimulusEvent& stimulus : full.stimuli) {
      dropped_frames += stimulus.dropped_frames;
      gaze_refreshes += static_cast<int64_t>(stimulus.present_s.size());
      for (const InvalidGaze& invalid : stimulus.invalid_gaze)
        ++(invalid.reason == "off_screen" ? gaze_off_image : gaze_invalid_other);
      if (stimulus.gaze_age_s) ++stimuli_with_latency;
      for (const std::optional<double>& age : stimulus.gaze_age_s.value_or(std::vector<std::optional<double>>{}))
        if (age) gaze_age_s.push_back(*age);
      for (size_t j = 1; j < stimulus.present_s.size(); ++j)
        frame_interval_s.push_back(stimulus.present_s[j] - stimulus.present_s[j - 1]);
    }
    EXPECT_EQ(fast.dropped_frames, dropped_frames);
    EXPECT_EQ(fast.gaze_refreshes, gaze_refreshes);
    EXPECT_EQ(fast.gaze_off_image, gaze_off_image);
    EXPECT_EQ(fast.gaze_invalid_other, gaze_invalid_other);
    EXPECT_EQ(fast.stimuli_with_latency, stimuli_with_latency);
    EXPECT_EQ(fast.gaze_age_s, gaze_age_s);
    EXPECT_EQ(fast.frame_interval_s, frame_interval_s);
  }
  std::map<int, std::string> block_names;  // from the full reader's events
  for (const json& event : log.events)
    if (event.value("event", "") == "block_start") {
      const std::string name = event.value("name", "");
      block_names[event.value("block", 0)] = name.empty() ? event.value("scene", "") : name;
    }
  EXPECT_EQ(scan.block_names, block_names);
}

TEST(SessionScan, TellsTheSameStoryAsTheSessionRecord) {
  const std::string path = write_rich_log("rich.jsonl");
  expect_same_story(path);
  const ScannedSession scan = scan_session_log(path);
  ASSERT_EQ(scan.trials.size(), 3u);  // trial 3 never ended
  EXPECT_EQ(scan.incomplete_trial, 3);
  EXPECT_EQ(scan.trials[2].answers, (std::vector<std::string>{"reference", "save"}));  // the resumed run's
  ASSERT_TRUE(scan.trials[2].saved_level);
  EXPECT_EQ(*scan.trials[2].saved_level, 15.0);
  EXPECT_EQ(scan.block_names.at(0), "courtyard");
  EXPECT_EQ(scan.block_names.at(1), "temple");  // unnamed: its scene
  EXPECT_EQ(scan.attention_errors, 1);
  EXPECT_TRUE(scan.excluded);
  EXPECT_EQ(scan.first_chain_error_line, 0);
}

TEST(SessionScan, TornTailsAndEditedLinesAreSeenAsTheFullReaderSeesThem) {
  const std::string path = write_rich_log("torn.jsonl");
  { std::ofstream(path, std::ios::app) << "{\"event\":\"trial_e"; }
  expect_same_story(path);
  EXPECT_EQ(scan_session_log(path).torn_tail_bytes, 17u);

  // An edited answer: still valid JSON, but the chain breaks at that line.
  const std::string edited = write_rich_log("edited.jsonl");
  std::ifstream in(edited);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  bytes.replace(bytes.find("\"answer\":\"same\""), 15, "\"answer\":\"diff\"");
  std::ofstream(edited, std::ios::trunc) << bytes;
  expect_same_story(edited);
  EXPECT_EQ(scan_session_log(edited).first_chain_error_line, 6);

  // Re-formatted by hand (spaces after colons), unchanged in content: the canonical fallback
  // still accepts the chain, as read_event_log does.
  const std::string spaced = write_rich_log("spaced.jsonl");
  std::ifstream spaced_in(spaced);
  std::string spaced_bytes((std::istreambuf_iterator<char>(spaced_in)), std::istreambuf_iterator<char>());
  const size_t line_end = spaced_bytes.find('\n', spaced_bytes.find("\"event\":\"trial_end\""));
  const size_t line_begin = spaced_bytes.rfind('\n', line_end - 1) + 1;
  std::string line = spaced_bytes.substr(line_begin, line_end - line_begin);
  for (size_t at = line.find("\":"); at != std::string::npos; at = line.find("\":", at + 3))
    line.insert(at + 2, 1, ' ');
  spaced_bytes.replace(line_begin, line_end - line_begin, line);
  std::ofstream(spaced, std::ios::trunc) << spaced_bytes;
  expect_same_story(spaced);
  EXPECT_EQ(scan_session_log(spaced).first_chain_error_line, 0);
}

TEST(SessionScan, RejectsWhatTheFullReaderRejects) {
  const auto expect_rejected = [](const std::string& name, const std::string& bytes, const std::string& message) {
    const std::string path = scratch_log(name);
    std::ofstream(path, std::ios::binary) << bytes;
    try {
      scan_session_log(path);
      ADD_FAILURE() << name << ": accepted by the scan";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(message), std::string::npos) << error.what();
    }
    // The full reader rejects it too (in its own words where its checks differ).
    EXPECT_THROW(read_session_record(read_event_log(path)), InputError) << name;
  };
  expect_rejected(
      "not_json.jsonl",
      "{\"event\":\"session_header\",\"schema_version\":1,\"study\":\"s\",\"participant\":\"p\"}\nnot json\n",
      ":2: not a JSON event");
  expect_rejected("array.jsonl", "[1,2]\n", ":1: not a JSON event");
  expect_rejected("schema.jsonl", "{\"event\":\"session_header\",\"schema_version\":99}\n", "schema_version 99");
  expect_rejected("no_header.jsonl", "{\"event\":\"trial_end\",\"trial\":0}\n", "expected a session_header");
  expect_rejected("empty.jsonl", "", "no complete event");
  expect_rejected("orphan.jsonl",
                  "{\"event\":\"session_header\",\"schema_version\":1,\"study\":\"s\",\"participant\":\"p\"}\n{"
                  "\"event\":\"trial_end\",\"trial\":4}\n",
                  ":2: trial_end: trial does not match");
  expect_rejected("type.jsonl",
                  "{\"event\":\"session_header\",\"schema_version\":1,\"study\":\"s\",\"participant\":\"p\"}\n{"
                  "\"event\":\"trial_start\",\"trial\":\"zero\"}\n",
                  ":2: an event has a field of the wrong type");
  expect_rejected("deep.jsonl",
                  "{\"event\":\"session_header\",\"schema_version\":1,\"study\":\"s\",\"participant\":\"p\"}\n" +
                      std::string(5000, '[') + "\n",
                  ":2: not a JSON event");
  EXPECT_THROW(scan_session_log(scratch_log("never_written.jsonl")), InputError);
}

TEST(SessionScan, KeepsTheIntervalsBetweenEachStimulusPresentTimes) {
  // Issue 38's frame intervals: consecutive present_s entries of one stimulus event; the gap between
  // two stimuli is not one. present_s is read leniently by the full reader (a value of another type
  // is left at its default), so the scan accepts it too and keeps no interval from it.
  const std::string path = scratch_log("present_times.jsonl");
  {
    EventLogWriter log(path, "", 0);
    log.append({{"event", "session_header"},
                {"schema_version", log_schema_version},
                {"study", "s"},
                {"participant", "p"},
                {"t", 0.0}});
    log.append({{"event", "block_start"}, {"block", 0}, {"name", "courtyard"}, {"scene", "x.glsl"}, {"t", 0.1}});
    log.append({{"event", "trial_start"},
                {"trial", 0},
                {"block", 0},
                {"condition", "level=5"},
                {"variant", ""},
                {"level", 5},
                {"attention_check", false},
                {"sequence", {0, 1}},
                {"t", 1.0}});
    log.append({{"event", "stimulus"}, {"trial", 0}, {"step", 0}, {"present_s", {1.0, 1.25, 1.75}}, {"t", 1.8}});
    log.append({{"event", "stimulus"}, {"trial", 0}, {"step", 0}, {"present_s", {3.0, 3.5}}, {"t", 3.6}});
    log.append({{"event", "stimulus"}, {"trial", 0}, {"step", 0}, {"present_s", {4.0, "x"}}, {"t", 4.1}});
    log.append({{"event", "stimulus"}, {"trial", 0}, {"step", 0}, {"present_s", "x"}, {"t", 4.2}});
    log.append({{"event", "response"}, {"trial", 0}, {"step", 1}, {"answer", "same"}, {"t", 4.3}});
    log.append({{"event", "trial_end"}, {"trial", 0}, {"t", 4.4}});
  }
  const ScannedSession scan = scan_session_log(path);
  ASSERT_EQ(scan.trials.size(), 1u);
  EXPECT_EQ(scan.trials[0].frame_interval_s, (std::vector<double>{0.25, 0.5, 0.5}));
  EXPECT_NO_THROW(read_session_record(read_event_log(path)));
}

TEST(SessionScan, ReadsEveryFieldItKeepsAsTheFullReaderReadsIt) {
  // Schema 3 stimulus fields (nulls where the tracker had no sample), a practice trial of a track,
  // a ramp trial, and a line with a key given twice (the last counts, for both readers).
  const std::string path = scratch_log("kept_fields.jsonl");
  {
    EventLogWriter log(path, "", 0);
    log.append({{"event", "session_header"},
                {"schema_version", log_schema_version},
                {"study", "s"},
                {"participant", "p"},
                {"t", 0.0}});
    log.append(to_json(TrialStartEvent{.stamp = {1.0, {}},
                                       .trial = 0,
                                       .block = 2,
                                       .condition = "c",
                                       .variant = "v",
                                       .level = 3.5,
                                       .sequence = {4, 5},
                                       .ramp_toward_reference = false,
                                       .practice = true,
                                       .track = 1}));
    StimulusEvent stimulus{.stamp = {1.5, {}}, .trial = 0, .step = 0, .stimulus = 4, .onset_s = 1.0};
    stimulus.present_s = {1.0, 1.0125, 1.05};
    stimulus.dropped_frames = 2;
    stimulus.gaze_acquired_s = std::vector<std::optional<double>>{0.99, std::nullopt, 1.04};
    stimulus.gaze_age_s = std::vector<std::optional<double>>{0.01, std::nullopt, 0.01};
    stimulus.present_clock = "steady";
    stimulus.invalid_gaze = {{0, "off_screen"}, {2, "no_data"}};
    log.append(to_json(stimulus));
    stimulus.gaze_age_s = std::vector<std::optional<double>>{};
    stimulus.present_clock = "vsync";
    log.append(to_json(stimulus));
    log.append(
        to_json(ResponseEvent{.stamp = {1.6, {}}, .trial = 0, .step = 3, .answer = "up", .key = "u", .rt_s = 0.2}));
    log.append(to_json(TrialEndEvent{.stamp = {1.7, {}}, .trial = 0}));
  }
  {  // a trial_start whose sequence is given twice, added by hand and re-chained
    EventLogFile log = read_event_log(path);
    std::string text;
    std::string chain;
    for (size_t i = 0; i < log.events.size(); ++i) {
      nlohmann::json event = log.events[i];
      event.erase("chain");
      // An invalid_gaze with an entry of the wrong shape: both readers keep none of it.
      if (event.value("present_clock", "") == "vsync")
        event["invalid_gaze"] = nlohmann::json::parse(R"([{"i": 1, "reason": "no_data"}, {"i": 1.5, "reason": "x"}])");
      std::string line = event.dump();
      if (event.value("event", "") == "trial_start") line.insert(1, "\"sequence\":[9,9,9],");
      chain = chain_of_text(chain, line, log.schema_version);
      line.insert(line.size() - 1, ",\"chain\":\"" + chain + "\"");
      text += line + "\n";
    }
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  }
  expect_same_story(path);
  const ScannedSession scan = scan_session_log(path);
  EXPECT_EQ(scan.first_chain_error_line, 0);
  ASSERT_EQ(scan.trials.size(), 1u);
  const ScannedTrial& trial = scan.trials[0];
  EXPECT_EQ(trial.block, 2);
  EXPECT_EQ(trial.sequence, (std::vector<int>{4, 5}));
  EXPECT_TRUE(trial.practice);
  EXPECT_EQ(trial.track, 1);
  EXPECT_FALSE(trial.ramp_toward_reference);
  EXPECT_EQ(trial.level, 3.5);
  EXPECT_EQ(trial.dropped_frames, 4);
  EXPECT_EQ(trial.stimuli_with_latency, 2);
  EXPECT_EQ(trial.gaze_age_s, (std::vector<double>{0.01, 0.01}));
  EXPECT_EQ(trial.gaze_refreshes, 6);
  EXPECT_EQ(trial.gaze_off_image, 1);
  EXPECT_EQ(trial.gaze_invalid_other, 1);
  EXPECT_EQ(trial.answer_steps, (std::vector<int>{3}));
  EXPECT_EQ(scan.present_clocks, (std::vector<std::string>{"steady", "vsync"}));
}

}  // namespace
}  // namespace fovlab
