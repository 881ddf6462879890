// Issue 19: adaptive blocks ([procedure.NAME], staircases) in the schedule, the session, resume,
// replay and the analysis. The levels a session logs are checked against the staircase rules
// applied here, trial by trial, to the answers logged before them.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"
#include "core/csv.h"
#include "core/input_error.h"
#include "protocols/session/replay.h"
#include "protocols/session/trials_export.h"
#include "study/log/schedule_check.h"
#include "study/log/log_events.h"
#include "study/schedule/adaptive_progress.h"
#include "study/schedule/quest_plus.h"
#include "study/schedule/staircase.h"
#include "tests/protocols/session/session_test_support.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::replay;
using test::resume_after_cut;
using test::simulated;
using test::study_fixture;
using test::trial_summary;

// tiny_2afc with eight levels and both blocks adaptive: 1-up-2-down from the easiest level and from
// the hardest (two interleaved staircases a block), 12 trials each, stopped at 4 reversals.
const char* kProcedure =
    "\n[procedure.stairs]\nkind = \"staircase\"\ndown = 2\nstep_sizes = [2, 1]\nstarts = [1, 16]\n"
    "max_trials = 12\nmax_reversals = 4\nreversals_averaged = 3\n";

std::string adaptive_text(const std::string& procedure = kProcedure, const std::string& block_procedure = "stairs") {
  std::string text = read_file(study_fixture("tiny_2afc"));
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    if (at == std::string::npos) throw std::logic_error("not in tiny_2afc: " + from);
    text.replace(at, from.size(), to);
  };
  replace("values = [2, 4, 8, 16]", "values = [1, 2, 3, 4, 6, 8, 12, 16]");
  for (const char* block : {"name = \"sphere\"", "name = \"primitives\""})
    replace(block, std::string(block) + "\nprocedure = \"" + block_procedure + "\"");
  return text + procedure;
}

StudyConfig adaptive_config(const std::string& procedure = kProcedure, const std::string& block_procedure = "stairs") {
  return parse_study_config_text(adaptive_text(procedure, block_procedure), study_fixture("tiny_2afc").string(),
                                 renderer_scene_catalog());
}

std::string config_error(const std::string& procedure, const std::string& block_procedure = "stairs") {
  try {
    adaptive_config(procedure, block_procedure);
  } catch (const InputError& error) {
    return error.what();
  }
  return "no error";
}

TEST(AdaptiveSchedule, EachBlockPlansItsInterleavedStaircasesToTheirMaxTrials) {
  const StudyConfig config = adaptive_config();
  ASSERT_EQ(config.procedures.size(), 1u);
  const StudyPlan plan = make_study_plan(config, "P1");
  ASSERT_EQ(plan.tracks.size(), 4u);  // two blocks x two starts
  // higher_is_better: the grid runs from the lowest max_steps (easiest to tell apart) up.
  EXPECT_EQ(plan.tracks[0].grid, (std::vector<double>{1, 2, 3, 4, 6, 8, 12, 16}));
  EXPECT_EQ(plan.tracks[0].staircase.start_index, 0);
  EXPECT_EQ(plan.tracks[1].staircase.start_index, 7);
  std::map<int, int> trials_of;
  int checks = 0;
  for (const Trial& trial : plan.trials) {
    if (trial.attention_check) {
      ++checks;
      continue;
    }
    ASSERT_GE(trial.track, 0);
    EXPECT_TRUE(trial.sequence.empty());  // chosen as the session runs
    EXPECT_EQ(plan.tracks[size_t(trial.track)].block, trial.block);
    ++trials_of[trial.track];
  }
  for (const auto& [staircase, count] : trials_of) EXPECT_EQ(count, 12) << staircase;
  EXPECT_GT(checks, 0);
  // The reference's interval alternates along each staircase's trials.
  std::map<int, int> firsts;
  for (const Trial& trial : plan.trials)
    if (trial.track >= 0) firsts[trial.track] += trial.reference_first ? 1 : 0;
  for (const auto& [staircase, count] : firsts) EXPECT_EQ(count, 6) << staircase;
  // A block without a procedure keeps constant stimuli.
  std::string text = adaptive_text();
  text.replace(text.find("procedure = \"stairs\"\n"), 21, "");
  const StudyPlan mixed = make_study_plan(
      parse_study_config_text(text, study_fixture("tiny_2afc").string(), renderer_scene_catalog()), "P1");
  EXPECT_EQ(mixed.tracks.size(), 2u);
}

TEST(AdaptiveSchedule, BadProceduresAreOneLineErrorsNamingTheField) {
  const auto has = [](const std::string& error, const std::string& part) {
    EXPECT_NE(error.find(part), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
  };
  EXPECT_EQ(config_error(kProcedure), "no error");
  has(config_error("\n[procedure.stairs]\nkind = \"quest\"\nmax_trials = 10\n"),
      "procedure.stairs.kind: expected \"staircase\"");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\nstep_sizes = [0]\nmax_trials = 10\n"),
      "procedure.stairs.step_sizes: expected whole numbers of grid steps, 1 or more, got 0");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\nstep_sizes = [9]\nmax_trials = 10\n"),
      "procedure.stairs.step_sizes: expected grid steps from 1 to 7, got 9");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\nstarts = [5]\nmax_trials = 10\n"),
      "procedure.stairs.starts: expected levels of the grid, got 5");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\nmax_trials = 0\n"),
      "procedure.stairs.max_trials: expected a value in [1, 10000]");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\n"), "procedure.stairs.max_trials");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\nmax_trials = 10\nmax_reversals = 10\n"),
      "procedure.stairs.max_reversals: expected fewer than max_trials (10)");
  has(config_error("\n[procedure.stairs]\nkind = \"staircase\"\nmax_trials = 6\n"),
      "procedure.stairs.reversals_averaged: expected fewer than max_trials (6)");
  has(config_error("\n[procedure.stairs]\nkind = \"weighted\"\ndown = 2\nmax_trials = 10\n"),
      "procedure.stairs.down: unknown key");
  has(config_error("\n[procedure.stairs]\nkind = \"weighted\"\neasier_steps = 0\nmax_trials = 10\n"),
      "procedure.stairs.easier_steps: expected a value in [1, 1000]");
  has(config_error(kProcedure, "steps"),
      "block[1].procedure: expected the name of a [procedure.NAME] table, got \"steps\"");
  // Answers that are right or wrong: not a rating.
  std::string rating = read_file(study_fixture("rating"));
  rating.replace(rating.find("[[block]]"), 9, "[[block]]\nprocedure = \"stairs\"");
  try {
    parse_study_config_text(rating + kProcedure, study_fixture("rating").string(), renderer_scene_catalog());
    ADD_FAILURE() << "a rating study took a staircase";
  } catch (const InputError& error) {
    has(error.what(),
        "procedure.stairs: an adaptive procedure needs answers that see the difference or not (2afc, pair)");
  }
}

// The logged level of each adaptive trial, against the rule applied here to the answers before it.
void expect_levels_follow_the_rule(const StudyPlan& plan, const SessionRecord& record) {
  std::vector<std::vector<bool>> answers(plan.tracks.size());
  for (const RecordedTrial& trial : record.trials) {
    if (!trial.start.track) continue;
    const size_t staircase = size_t(*trial.start.track);
    const AdaptiveTrack& planned = plan.tracks.at(staircase);
    const StaircaseState state = replay_staircase(planned.staircase, answers[staircase], int(planned.grid.size()));
    EXPECT_FALSE(state.finished) << "trial " << trial.index << " ran after its staircase stopped";
    ASSERT_TRUE(trial.start.level);
    EXPECT_EQ(*trial.start.level, planned.grid[size_t(state.index)]) << "trial " << trial.index;
    ASSERT_EQ(trial.responses.size(), 1u);
    answers[staircase].push_back(trial.responses[0].answer == "different");  // question "same": seen
  }
  // Every staircase ran until it stopped (12 trials or 4 reversals).
  for (size_t i = 0; i < answers.size(); ++i) {
    const StaircaseState state =
        replay_staircase(plan.tracks[i].staircase, answers[i], int(plan.tracks[i].grid.size()));
    EXPECT_TRUE(state.finished) << "staircase " << i;
  }
}

TEST(AdaptiveSession, LevelsFollowTheAnswersAStoppedStaircaseSkipsTheRestAndReplayVerifies) {
  const StudyConfig config = adaptive_config();
  const StudyPlan plan = make_study_plan(config, "P1");
  const fs::path results = fresh_folder("adaptive");
  const SessionOutcome outcome = run_session(config, simulated(results));
  ASSERT_TRUE(outcome.finished);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  expect_levels_follow_the_rule(plan, record);
  EXPECT_LT(record.trials.size(), plan.trials.size()) << "no staircase stopped at its reversals";
  EXPECT_EQ(outcome.trials_completed, int(record.trials.size()));
  // session_end counts the trials run, not the schedule's upper bound.
  for (const nlohmann::json& event : read_event_log(outcome.log_path).events)
    if (event_kind(event) == "session_end") {
      EXPECT_EQ(event["completed_trials"], int(record.trials.size()));
    }
  std::set<double> levels;
  for (const RecordedTrial& trial : record.trials)
    if (trial.start.level) levels.insert(*trial.start.level);
  EXPECT_GE(levels.size(), 4u) << "the staircases hardly moved";
  const ReplayOutcome replayed = replay(outcome.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());

  // A log whose level is not the staircase's is a difference (schedule check of resume and replay).
  SessionRecord forged = record;
  for (RecordedTrial& trial : forged.trials)
    if (trial.start.track && trial.index > 10) {
      trial.start.level = *trial.start.level == 16.0 ? 1.0 : 16.0;
      break;
    }
  const ScheduleCheck check = check_log_against_schedule(forged, plan);
  ASSERT_EQ(check.differences.size(), 1u);
  EXPECT_NE(check.differences[0].find("differs from the schedule"), std::string::npos) << check.differences[0];
  // A trial logged under another track than the schedule's (the analysis attributes answers by it).
  SessionRecord retracked = record;
  for (RecordedTrial& trial : retracked.trials)
    if (trial.start.track) {
      trial.start.track = *trial.start.track == 0 ? 1 : 0;
      break;
    }
  ASSERT_EQ(check_log_against_schedule(retracked, plan).differences.size(), 1u);
  EXPECT_NE(check_log_against_schedule(retracked, plan).differences[0].find("track"), std::string::npos);
  // A trial missing before a later one that the schedule runs.
  SessionRecord gap = record;
  gap.trials.erase(gap.trials.begin() + 3);
  EXPECT_NE(check_log_against_schedule(gap, plan).differences.at(0).find("missing from the log"), std::string::npos);
}

TEST(AdaptiveSession, ACrashAnywhereResumesToTheSameStaircases) {
  const StudyConfig config = adaptive_config();
  const fs::path results = fresh_folder("adaptive-resume");
  const SessionOutcome whole_run = run_session(config, simulated(results / "whole"));
  ASSERT_TRUE(whole_run.finished);
  const std::vector<std::string> expected = trial_summary(whole_run.log_path);
  const std::string whole = read_file(whole_run.log_path);
  std::vector<size_t> line_ends;
  for (size_t i = 0; i < whole.size(); ++i)
    if (whole[i] == '\n') line_ends.push_back(i + 1);
  const std::vector<size_t> cuts = {line_ends[5], line_ends[line_ends.size() / 3], line_ends[line_ends.size() / 2] - 5,
                                    line_ends[line_ends.size() - 3]};
  for (size_t cut : cuts) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    const auto [resumed, log_path] = resume_after_cut(config, simulated(results), results, whole, cut);
    EXPECT_TRUE(resumed.resumed);
    EXPECT_TRUE(resumed.finished);
    EXPECT_EQ(trial_summary(log_path), expected);
    EXPECT_EQ(replay(log_path).difference_count, 0);
  }
}

TEST(AdaptiveAnalysis, EachStaircasesThresholdIsTheMeanOfItsLastReversals) {
  const StudyConfig config = adaptive_config();
  const StudyPlan plan = make_study_plan(config, "P2");
  const fs::path results = fresh_folder("adaptive-analysis");
  const SessionOutcome outcome = run_session(config, simulated(results, "P2"));
  ASSERT_TRUE(outcome.finished);
  const analysis::StudyData data = analysis::load_study({outcome.log_path});
  analysis::AnalysisOptions options;
  options.bootstrap_samples = 50;  // the fits are not what this test checks
  const analysis::AnalysisResult result = analysis::analyse_study(data, options);
  ASSERT_EQ(result.participants.size(), 1u);
  const std::vector<analysis::AdaptiveTrackResult>& tracks = result.participants[0].tracks;
  ASSERT_EQ(tracks.size(), plan.tracks.size());
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  for (size_t i = 0; i < tracks.size(); ++i) {
    SCOPED_TRACE("staircase " + std::to_string(i));
    // The logged levels and answers of this staircase, and its reversals recomputed from the levels:
    // a reversal is where the direction of the level's change turns.
    std::vector<double> levels;
    std::vector<bool> seen;
    for (const RecordedTrial& trial : record.trials)
      if (trial.start.track == int(i)) {
        levels.push_back(*trial.start.level);
        seen.push_back(trial.responses.at(0).answer == "different");
      }
    EXPECT_EQ(tracks[i].levels, levels);
    EXPECT_EQ(tracks[i].seen, seen);
    EXPECT_EQ(tracks[i].procedure, "stairs");
    EXPECT_EQ(tracks[i].start_level, std::optional<double>(i % 2 == 0 ? 1.0 : 16.0));
    EXPECT_EQ(tracks[i].kind, "staircase");
    EXPECT_TRUE(tracks[i].stopped);
    const StaircaseState state = replay_staircase(plan.tracks[i].staircase, seen, int(plan.tracks[i].grid.size()));
    std::vector<double> reversal_levels;
    for (int trial : tracks[i].reversal_trials) reversal_levels.push_back(levels.at(size_t(trial)));
    ASSERT_EQ(reversal_levels.size(), state.reversal_indices.size());
    for (size_t r = 0; r < reversal_levels.size(); ++r)
      EXPECT_EQ(reversal_levels[r], plan.tracks[i].grid[size_t(state.reversal_indices[r])]);
    if (reversal_levels.size() >= 3) {
      ASSERT_TRUE(tracks[i].threshold);
      const double mean = (reversal_levels[reversal_levels.size() - 1] + reversal_levels[reversal_levels.size() - 2] +
                           reversal_levels[reversal_levels.size() - 3]) /
                          3.0;
      EXPECT_DOUBLE_EQ(*tracks[i].threshold, mean);
    } else {
      EXPECT_FALSE(tracks[i].threshold);
      EXPECT_FALSE(tracks[i].note.empty());
    }
  }
}

// The same study with QUEST+: one track a block, 16 trials at most, stopped once the threshold's
// credible interval is at most 4 wide.
const char* kQuestPlus =
    "\n[procedure.quest]\nkind = \"quest_plus\"\nshape = \"logistic\"\nmax_trials = 16\nstop_interval_width = 4\n";

TEST(AdaptiveSession, QuestPlusChoosesEachLevelFromTheAnswersBeforeItAndAnalysesToItsPosterior) {
  const StudyConfig config = adaptive_config(kQuestPlus, "quest");
  const StudyPlan plan = make_study_plan(config, "P1");
  ASSERT_EQ(plan.tracks.size(), 2u);
  const QuestPlusRule& rule = plan.tracks[0].quest;
  EXPECT_FALSE(rule.rising);               // higher max_steps look more like the reference
  EXPECT_EQ(rule.guess, 0.05);             // 2afc "same": the nominal false-alarm rate
  EXPECT_EQ(rule.thresholds.size(), 41u);  // the defaults
  const fs::path results = fresh_folder("quest");
  const SessionOutcome outcome = run_session(config, simulated(results));
  ASSERT_TRUE(outcome.finished);
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  std::vector<std::vector<bool>> answers(plan.tracks.size());
  for (const RecordedTrial& trial : record.trials) {
    if (!trial.start.track) continue;
    const size_t track = size_t(*trial.start.track);
    const QuestPlus quest(plan.tracks[track].quest, plan.tracks[track].grid);
    const QuestPlusState state = quest.replay(answers[track]);
    EXPECT_FALSE(state.finished) << "trial " << trial.index;
    EXPECT_EQ(*trial.start.level, plan.tracks[track].grid[size_t(state.index)]) << "trial " << trial.index;
    answers[track].push_back(trial.responses.at(0).answer == "different");
  }
  EXPECT_EQ(replay(outcome.log_path).difference_count, 0);

  analysis::AnalysisOptions options;
  options.bootstrap_samples = 50;
  const analysis::AnalysisResult result = analysis::analyse_study(analysis::load_study({outcome.log_path}), options);
  const std::vector<analysis::AdaptiveTrackResult>& tracks = result.participants.at(0).tracks;
  ASSERT_EQ(tracks.size(), 2u);
  for (size_t i = 0; i < tracks.size(); ++i) {
    const QuestPlus quest(plan.tracks[i].quest, plan.tracks[i].grid);
    const QuestPlusState state = quest.replay(answers[i]);
    EXPECT_TRUE(state.finished);
    const QuestPlusEstimate estimate = quest.estimate(state.posterior);
    EXPECT_EQ(tracks[i].kind, "quest_plus");
    EXPECT_EQ(tracks[i].threshold, std::optional<double>(estimate.threshold_mean));
    EXPECT_EQ(tracks[i].threshold_lower, std::optional<double>(estimate.threshold_lower));
    EXPECT_EQ(tracks[i].threshold_upper, std::optional<double>(estimate.threshold_upper));
    EXPECT_LE(*tracks[i].threshold_lower, *tracks[i].threshold);
    EXPECT_GE(*tracks[i].threshold_upper, *tracks[i].threshold);
  }

  // A cut log resumes to the same trials.
  const std::string whole = read_file(outcome.log_path);
  const size_t cut = whole.find('\n', whole.find("\"trial_end\"", whole.size() / 2)) + 1;
  const auto [resumed, log_path] = resume_after_cut(config, simulated(results), results, whole, cut);
  EXPECT_TRUE(resumed.resumed);
  EXPECT_EQ(trial_summary(log_path), trial_summary(outcome.log_path));
}

// trials.csv names each adaptive trial's track (its index as logged, as adaptive_tracks.csv names
// it), the track's procedure and kind; constant-stimuli trials and attention checks leave them empty.
TEST(AdaptiveExport, TrialsCsvNamesEachAdaptiveTrialsTrack) {
  // The first block on staircases, the second on QUEST+.
  std::string text = adaptive_text(std::string(kProcedure) + kQuestPlus);
  const std::string second = "name = \"primitives\"\nprocedure = \"stairs\"";
  text.replace(text.find(second), second.size(), "name = \"primitives\"\nprocedure = \"quest\"");
  const StudyConfig config =
      parse_study_config_text(text, study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  const fs::path results = fresh_folder("adaptive-export");
  const SessionOutcome outcome = run_session(config, simulated(results));
  ASSERT_TRUE(outcome.finished);
  const std::vector<CsvRow> rows = read_csv_rows(export_trials_csv({outcome.log_path}), "trials.csv");
  ASSERT_GT(rows.size(), 1u);
  const std::vector<std::string>& header = rows.front().cells;
  const auto column = [&](const std::string& name) {
    const auto at = std::find(header.begin(), header.end(), name);
    EXPECT_NE(at, header.end()) << name;
    return static_cast<size_t>(at - header.begin());
  };
  const size_t track = column("track"), procedure = column("track_procedure"), kind = column("track_kind");
  const size_t attention = column("attention_check"), block = column("block");
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  ASSERT_EQ(rows.size(), record.trials.size() + 1);
  std::set<std::string> kinds;
  for (size_t i = 1; i < rows.size(); ++i) {
    const std::vector<std::string>& cells = rows[i].cells;
    const RecordedTrial& trial = record.trials[i - 1];
    SCOPED_TRACE("trial " + std::to_string(trial.index));
    if (cells[attention] == "true") {
      EXPECT_EQ(cells[track] + cells[procedure] + cells[kind], "");
      continue;
    }
    ASSERT_TRUE(trial.start.track.has_value());
    EXPECT_EQ(cells[track], std::to_string(*trial.start.track));
    EXPECT_EQ(cells[procedure], cells[block] == "0" ? "stairs" : "quest");
    EXPECT_EQ(cells[kind], cells[block] == "0" ? "staircase" : "quest_plus");
    kinds.insert(cells[kind]);
  }
  EXPECT_EQ(kinds, (std::set<std::string>{"staircase", "quest_plus"}));

  // Constant stimuli: the columns are there, empty.
  const SessionOutcome constant =
      run_session(parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog()),
                  simulated(fresh_folder("constant-export")));
  const std::vector<CsvRow> constant_rows = read_csv_rows(export_trials_csv({constant.log_path}), "trials.csv");
  ASSERT_GT(constant_rows.size(), 1u);
  EXPECT_EQ(constant_rows.front().cells, header);
  for (size_t i = 1; i < constant_rows.size(); ++i)
    EXPECT_EQ(constant_rows[i].cells[track] + constant_rows[i].cells[procedure] + constant_rows[i].cells[kind], "");
}

TEST(AdaptiveSchedule, BadQuestPlusProceduresAreOneLineErrorsNamingTheField) {
  const auto error = [](const std::string& keys) {
    return config_error("\n[procedure.quest]\nkind = \"quest_plus\"\n" + keys, "quest");
  };
  const auto has = [](const std::string& text, const std::string& part) {
    EXPECT_NE(text.find(part), std::string::npos) << text;
    EXPECT_EQ(text.find('\n'), std::string::npos) << text;
  };
  EXPECT_EQ(error("max_trials = 20\n"), "no error");
  has(error("max_trials = 20\nshape = \"probit\"\n"), "procedure.quest.shape: expected \"logistic\"");
  has(error("max_trials = 20\nthresholds = [4, 2]\n"),
      "procedure.quest.thresholds: expected one or more values, ascending");
  has(error("max_trials = 20\nprior_mean = 100\nprior_sd = 0.5\n"),
      "procedure.quest.prior_mean: expected a prior with mass on the threshold grid");
  has(error("max_trials = 20\nprior_mean = 4\n"), "procedure.quest.prior_mean: expected prior_sd too");
  has(error("max_trials = 20\nstop_entropy_bits = 50\n"),
      "procedure.quest.stop_entropy_bits: expected 0 (none) or a value in (0,");
  has(error("max_trials = 20\nstop_interval_width = 20\n"),
      "procedure.quest.stop_interval_width: expected 0 (none) or a width below");
  has(error("max_trials = 20\nguess_rate = 0.97\n"),
      "procedure.quest.lapses: expected values of at least 0 with guess_rate + lapse below 1");
  has(error("max_trials = 20\nslopes = [0, 1]\n"), "procedure.quest.slopes: expected values above 0");
  has(error("max_trials = 20\nshape = \"weibull\"\nthresholds = [0, 8]\n"),
      "procedure.quest.thresholds: expected values above 0");
  has(error("max_trials = 20\nstarts = [1]\n"), "procedure.quest.starts: unknown key");
  has(error(""), "procedure.quest.max_trials");
}

}  // namespace
}  // namespace fovlab
