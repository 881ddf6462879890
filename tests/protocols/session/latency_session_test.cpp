// Gaze-to-present latency in the log (schema 3): every refresh of a stimulus logs its gaze sample's
// acquisition time and its age at present time, and the event names the present clock. On the
// headless presenter's virtual clock the age is exact: a synthetic sample stamped 40 ms old, shown
// at the next refresh, is 40 ms + one refresh period old when presented. Both log readers enforce
// the new fields' types alike, schema 2 logs (no latency) are still read, and the analysis reports
// the median and 95th percentile per participant.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"
#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "study/log/session_scan.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "tests/protocols/session/session_test_support.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::simulated;
using test::study_fixture;

constexpr double kAgeS = 0.040;
constexpr double kRefreshS = 1.0 / 60.0;  // tiny_2afc's display.refresh_hz

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  size_t begin = 0;
  while (begin < text.size()) {
    const size_t end = text.find('\n', begin);
    lines.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

// One headless tiny_2afc session whose synthetic gaze samples are 40 ms old, run once for the suite.
class SessionLatency : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    results_ = new fs::path(fresh_folder("latency"));
    SessionOptions options = simulated(*results_);
    options.gaze = "synthetic:seed=3,age_ms=40";
    outcome_ = new SessionOutcome(
        run_session(parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog()), options));
  }
  static void TearDownTestSuite() {
    delete outcome_;
    delete results_;
  }
  static fs::path* results_;
  static SessionOutcome* outcome_;
};
fs::path* SessionLatency::results_ = nullptr;
SessionOutcome* SessionLatency::outcome_ = nullptr;

TEST_F(SessionLatency, EveryRefreshLogsItsSampleTimeAndAgeOnTheVirtualClock) {
  const SessionRecord record = read_session_record(read_event_log(outcome_->log_path));
  EXPECT_EQ(record.header.value("schema_version", 0), log_schema_version);
  EXPECT_EQ(record.header.value("gaze", ""), "synthetic:seed=3,age_ms=40");
  int stimuli = 0;
  size_t refreshes = 0;
  for (const RecordedTrial& trial : record.trials) {
    for (const StimulusEvent& stimulus : trial.stimuli) {
      ++stimuli;
      EXPECT_EQ(stimulus.present_clock, "virtual");
      const std::vector<double>& present = stimulus.present_s;
      ASSERT_TRUE(stimulus.gaze_acquired_s && stimulus.gaze_age_s);
      const std::vector<std::optional<double>>& acquired = *stimulus.gaze_acquired_s;
      const std::vector<std::optional<double>>& ages = *stimulus.gaze_age_s;
      ASSERT_EQ(acquired.size(), present.size());
      ASSERT_EQ(ages.size(), present.size());
      for (size_t i = 0; i < present.size(); ++i) {
        // Asked at the previous refresh (or the onset), stamped 40 ms before that, shown one
        // period later: 40 ms + 16.67 ms, to rounding.
        ASSERT_TRUE(ages[i] && acquired[i]) << "refresh " << i;
        EXPECT_NEAR(*ages[i], kAgeS + kRefreshS, 1e-9) << "refresh " << i;
        EXPECT_NEAR(present[i] - *acquired[i], *ages[i], 1e-12);
        ++refreshes;
      }
    }
  }
  EXPECT_GT(stimuli, 0);
  // The run's own summary: every refresh, the same age.
  ASSERT_EQ(outcome_->gaze_age_s.size(), refreshes);
  for (const double age : outcome_->gaze_age_s) EXPECT_NEAR(age, kAgeS + kRefreshS, 1e-9);
  EXPECT_EQ(outcome_->present_clock, "virtual");
  EXPECT_EQ(outcome_->dropped_frames, 0);
  const analysis::LatencySummary summary = analysis::summarise_latency(outcome_->gaze_age_s);
  EXPECT_NEAR(*summary.median_ms, 1e3 * (kAgeS + kRefreshS), 1e-6);  // 56.667 ms
  EXPECT_NEAR(*summary.p95_ms, 1e3 * (kAgeS + kRefreshS), 1e-6);
}

TEST_F(SessionLatency, ReplayStillReproducesTheFramesFromTheLoggedPositions) {
  ReplayOptions options;
  options.log_path = outcome_->log_path;
  options.validation = true;
  const ReplayOutcome replayed = replay_session(options);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
  EXPECT_EQ(replayed.integrity.status, LogStatus::sealed);
}

TEST_F(SessionLatency, AnalysisReportsMedianAndP95PerParticipant) {
  const ScannedSession scanned = scan_session_log(outcome_->log_path);
  ASSERT_EQ(scanned.present_clocks, std::vector<std::string>{"virtual"});
  const analysis::StudyData data = analysis::load_study({outcome_->log_path});
  ASSERT_EQ(data.participants.size(), 1u);
  const analysis::ParticipantData& participant = data.participants.front();
  EXPECT_TRUE(participant.latency_recorded);
  EXPECT_EQ(participant.latency.refreshes, outcome_->gaze_age_s.size());
  EXPECT_NEAR(*participant.latency.median_ms, 1e3 * (kAgeS + kRefreshS), 1e-6);
  EXPECT_NEAR(*participant.latency.p95_ms, 1e3 * (kAgeS + kRefreshS), 1e-6);
  EXPECT_EQ(participant.dropped_frames, 0);
  EXPECT_EQ(participant.present_clock, "virtual");
  const analysis::AnalysisResult result = analysis::analyse_study(data, analysis::AnalysisOptions{});
  ASSERT_EQ(result.participants.size(), 1u);
  EXPECT_TRUE(result.participants.front().latency_recorded);
  EXPECT_EQ(result.participants.front().latency.median_ms, participant.latency.median_ms);
}

// A stimulus line of the session's log with `key`'s value replaced (the chain is left as it is:
// the type check refuses the line before any chain is looked at).
std::string forged_log(const std::string& log, const std::string& key, const nlohmann::json& value) {
  std::string out;
  bool done = false;
  for (const std::string& line : lines_of(log)) {
    nlohmann::json event = nlohmann::json::parse(line);
    if (!done && event.value("event", "") == "stimulus") {
      event[key] = value;
      done = true;
    }
    out += event.dump() + "\n";
  }
  return out;
}

TEST_F(SessionLatency, BothReadersRefuseLatencyFieldsOfTheWrongType) {
  const std::string log = read_file(outcome_->log_path);
  const fs::path folder = *results_ / "forged";
  fs::create_directories(folder);
  const std::vector<std::pair<std::string, nlohmann::json>> forgeries = {
      {"gaze_age_s", nlohmann::json::array({0.05, "0.05"})},  // a string among the ages
      {"gaze_age_s", "0.05"},
      {"gaze_acquired_s", nlohmann::json::array({true})},
      {"present_clock", 3},
      {"dropped_frames", "2"},
  };
  int index = 0;
  for (const auto& [key, value] : forgeries) {
    SCOPED_TRACE(key + " = " + value.dump());
    const fs::path path = folder / ("forged" + std::to_string(index++) + ".jsonl");
    std::ofstream(path, std::ios::binary) << forged_log(log, key, value);
    try {
      read_session_record(read_event_log(path.string()));
      ADD_FAILURE() << "the full reader accepted it";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("wrong type"), std::string::npos) << error.what();
    }
    try {
      scan_session_log(path.string());
      ADD_FAILURE() << "the fast scan accepted it";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find("wrong type"), std::string::npos) << error.what();
    }
  }
  // Nulls (a refresh without a sample) are of the right type for both; the edited line then only
  // breaks the chain.
  const fs::path nulls = folder / "nulls.jsonl";
  std::ofstream(nulls, std::ios::binary) << forged_log(log, "gaze_age_s", nlohmann::json::array({nullptr, 0.05}));
  EXPECT_EQ(read_session_record(read_event_log(nulls.string())).integrity.status, LogStatus::broken);
  const ScannedSession scanned = scan_session_log(nulls.string());
  EXPECT_EQ(scanned.integrity.status, LogStatus::broken);
}

// A schema 2 log (from the fuzz corpus: a sealed rating session written before latency was
// logged) is still read by both readers and analysed, its latency "not recorded".
TEST(SessionScanLatency, Schema2LogsAreReadWithoutLatency) {
  const std::string path =
      (fs::path(FOVLAB_SOURCE_DIR) / "tests/fuzz/corpus/log/22_schema2_rating_sealed.jsonl").string();
  const SessionRecord record = read_session_record(read_event_log(path));
  EXPECT_EQ(record.header.value("schema_version", 0), 2);
  EXPECT_EQ(record.integrity.status, LogStatus::sealed);
  const ScannedSession scanned = scan_session_log(path);
  EXPECT_EQ(scanned.integrity.status, LogStatus::sealed);
  EXPECT_TRUE(scanned.present_clocks.empty());
  ASSERT_FALSE(scanned.trials.empty());
  for (const ScannedTrial& trial : scanned.trials) {
    EXPECT_EQ(trial.stimuli_with_latency, 0);
    EXPECT_TRUE(trial.gaze_age_s.empty());
  }
  const analysis::StudyData data = analysis::load_study({path});
  ASSERT_EQ(data.participants.size(), 1u);
  EXPECT_FALSE(data.participants.front().latency_recorded);
  EXPECT_FALSE(data.participants.front().latency.median_ms.has_value());
  EXPECT_EQ(data.participants.front().present_clock, "");
}

}  // namespace
}  // namespace fovlab
