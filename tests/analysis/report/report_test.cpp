#include "analysis/report/report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/temp_dir.h"

namespace fovlab::analysis {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const char* const kParkScene = "park, \"north\"";  // a comma and quotes: the CSV must quote it

using fovlab::testing::TempDir;  // a fresh folder, removed at the end of the test

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// RFC 4180 reader: quoted cells may hold commas, doubled quotes and line breaks.
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      row.push_back(cell);
      cell.clear();
    } else if (c == '\n') {
      row.push_back(cell);
      cell.clear();
      rows.push_back(row);
      row.clear();
    } else {
      cell += c;
    }
  }
  EXPECT_FALSE(quoted) << "unterminated quote";
  EXPECT_TRUE(cell.empty() && row.empty()) << "no newline after the last row";
  return rows;
}

PsychometricFit logistic_fit(double threshold) {
  PsychometricFit fit;
  fit.model.shape = PsychometricShape::logistic;
  fit.model.rising = false;
  fit.model.guess = 0.5;
  fit.model.parameters = {threshold, 0.4, 0.02};
  fit.log_likelihood = -12.5;
  fit.deviance = 1.25;
  fit.degrees_of_freedom = 0;
  fit.deviance_p_value = kNaN;
  fit.threshold_interval = {8.0, 13.0};
  fit.slope_interval = {kNaN, kNaN};
  fit.lapse_interval = {0.0, 0.05};
  fit.bootstrap_samples = 998;
  fit.bootstrap_failures = 2;
  fit.converged = true;
  fit.note = "";
  return fit;
}

ConditionRow condition(const GroupKey& group, double level, uint64_t n, uint64_t k) {
  ConditionRow row;
  row.group = group;
  row.condition = "level=" + std::to_string(static_cast<int>(level));
  row.level = level;
  row.n = n;
  row.k = k;
  row.proportion = static_cast<double>(k) / static_cast<double>(n);
  row.p_value = 0.0123;
  row.log10_p = -1.91;
  row.p_holm = 0.0369;
  row.stars = "*";
  row.interval = {0.25, 0.875};
  return row;
}

// A headline as a pair study's analysis gives it: the mean over participants with its t interval.
Headline estimated_headline(const GroupKey& group) {
  Headline headline;
  headline.group = group;
  headline.quantity = "threshold";
  headline.method = "mean over participants, 95 % Student-t interval";
  headline.aims_at = "the participants' mean threshold";
  headline.value = 12.5;
  headline.lower = 11.75;
  headline.upper = 13.25;
  headline.flags = {"lapse at its bound (0)", "slope at its bound"};
  headline.notes = {"2 participants censored at the best level"};
  headline.participants = 8;
  headline.paper_rule = "Polychronakis et al. 2021, 4.7";
  headline.paper_value = 16.0;
  headline.paper_difference = "the walk reports the last level not distinguished, not the crossing";
  return headline;
}

// A fit whose threshold lies outside the levels: the struct holds a number that must not be printed.
Headline not_estimable_headline(const GroupKey& group) {
  Headline headline;
  headline.group = group;
  headline.quantity = "threshold";
  headline.method = "logistic fit, 95 % profile-likelihood interval";
  headline.aims_at = "the level where p_see = 1/2";
  headline.status = HeadlineStatus::not_estimable;
  headline.reason = "the fit's threshold -55.333 lies outside the tested levels 4 to 64";
  headline.value = -55.333;
  headline.lower = -std::numeric_limits<double>::infinity();
  headline.upper = 5.12;
  headline.participants = 3;
  headline.pooled_fit = 14.5;
  headline.pooled_fit_lower = 13.0;
  headline.pooled_fit_upper = 16.25;
  return headline;
}

// Two groups (one with a troublesome scene name), a logistic fit, a participant with thresholds, an
// excluded one without, and a left-out log.
AnalysisResult sample_result() {
  const GroupKey park{kParkScene, "blur"};
  const GroupKey city{"city", ""};
  AnalysisResult result;
  result.study = "demo <study>";
  result.protocol = ProtocolKind::pair;
  result.level_parameter = "foveal_deg";
  result.higher_is_better = true;
  result.levels = {5, 10, 20};
  result.alternative = Alternative::greater;
  result.alpha = 0.05;
  result.guess_rate = 0.5;
  result.guess_rate_source = "attention checks (12 of 240)";
  result.inputs = {"results/demo/P001/events.jsonl", "results/demo/P002/events.jsonl"};

  result.conditions = {condition(park, 5, 12, 3), condition(park, 10, 12, 8), condition(park, 20, 12, 12),
                       condition(city, 5, 9, 6),  condition(city, 10, 12, 6), condition(city, 20, 12, 11)};
  result.conditions[1].p_value = kNaN;  // must come out empty (CSV) and null (JSON)
  ConditionRow no_level = condition(city, 0, 4, 2);
  no_level.condition = "reference";
  no_level.level.reset();
  result.conditions.push_back(no_level);

  ParticipantRow p1;
  p1.participant = "P001";
  p1.log_path = "results/demo/P001/events.jsonl";
  p1.complete_trials = 120;
  p1.attention_checks = 6;
  p1.attention_errors = 0;
  p1.session_ended = true;
  p1.thresholds = {{park, 10.0, ""}, {city, std::nullopt, "every step answered correctly, censored"}};
  p1.latency_recorded = true;
  p1.latency.refreshes = 720;
  p1.latency.median_ms = 56.5;
  p1.latency.p95_ms = 73.25;
  p1.dropped_frames = 3;
  p1.present_clock = "after_queue_present";
  p1.practice_trials = 4;
  p1.validation.attempts = 3;  // one failed, two passed
  p1.validation.passed = 2;
  p1.validation.mean_accuracy_deg = 0.5;
  p1.validation.worst_accuracy_deg = 0.75;
  p1.validation.mean_precision_deg = 0.125;
  p1.frame_intervals = summarise_frame_intervals({0.016, 0.016, 0.017, 0.016, 0.034}, 60.0);
  ParticipantRow p2;
  p2.participant = "P002";
  p2.log_path = "results/demo/P002/events.jsonl";
  p2.complete_trials = 80;
  p2.attention_checks = 6;
  p2.attention_errors = 4;
  p2.excluded = true;
  p2.dropped_frames = 1;  // a schema 2 log: no latency recorded
  result.participants = {p1, p2};
  result.frame_intervals = pool_frame_intervals({&p1.frame_intervals});  // analyse_study pools the included (P001)

  GroupThreshold t_park;
  t_park.group = park;
  t_park.definition = "the smallest level from which every larger level is judged identical";
  t_park.level = 10.0;
  t_park.mean = 10.0;
  t_park.participants_with_threshold = 1;
  GroupThreshold t_city;
  t_city.group = city;
  t_city.definition = t_park.definition;
  t_city.note = "no participant has a threshold";
  t_city.participants_without_threshold = 1;
  result.thresholds = {t_park, t_city};

  GroupFit fit;
  fit.group = park;
  fit.data = {{5, 12, 9}, {10, 12, 4}, {20, 12, 0}};
  fit.fits = {logistic_fit(10.5)};
  fit.not_fitted = {"weibull: did not converge"};
  result.fits = {fit};

  result.left_out = {{"results/demo/P003/events.jsonl", "no complete trials (session log torn)"}};
  result.headlines = {estimated_headline(park), not_estimable_headline(city)};
  return result;
}

// A number as the CSV files write it (10 significant digits).
std::string csv_number_for_test(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

std::vector<std::string> operator+(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

std::vector<std::string> file_names(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  for (const std::string& path : paths) names.push_back(fs::path(path).filename().string());
  return names;
}

TEST(AnalysisReport, WritesEveryFileAndReturnsItsPath) {
  TempDir dir("files");
  const fs::path out = dir.path() / "nested" / "report";  // created, parents too
  const std::vector<std::string> paths = write_analysis_report(sample_result(), out.string());
  EXPECT_EQ(file_names(paths),
            (std::vector<std::string>{"headline.csv", "conditions.csv", "participants.csv", "thresholds.json",
                                      "share_per_level.svg", "psychometric_park___north__blur.svg",
                                      "participant_thresholds_park___north_.svg", "thresholds_histogram.svg",
                                      "frame_intervals.svg", "frame_intervals_P001.svg", "report.html"}));
  for (const std::string& path : paths) {
    EXPECT_EQ(fs::path(path).parent_path(), out);
    EXPECT_TRUE(fs::is_regular_file(path)) << path;
    EXPECT_GT(fs::file_size(path), 0u) << path;
  }
  // Nothing else (no temporary files left behind).
  EXPECT_EQ(static_cast<std::size_t>(std::distance(fs::directory_iterator(out), fs::directory_iterator())),
            paths.size());
}

TEST(AnalysisReport, ConditionsCsvHasOneQuotedRowPerCondition) {
  TempDir dir("conditions");
  const AnalysisResult result = sample_result();
  write_analysis_report(result, dir.path().string());
  const std::string text = read_text(dir.path() / "conditions.csv");
  EXPECT_NE(text.find("\"park, \"\"north\"\"\""), std::string::npos) << "RFC 4180 quoting";
  const auto rows = parse_csv(text);
  ASSERT_EQ(rows.size(), result.conditions.size() + 1);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"study", "protocol", "scene", "variant", "method", "condition", "level",
                                               "n", "k", "proportion", "ci_lower", "ci_upper", "p_value", "p_holm",
                                               "stars", "alternative", "mean_rating", "sd_rating", "log10_p"}));
  for (const auto& row : rows) ASSERT_EQ(row.size(), 19u);
  EXPECT_EQ(rows[1],
            (std::vector<std::string>{"demo <study>", "pair", kParkScene, "blur", "", "level=5", "5", "12", "3", "0.25",
                                      "0.25", "0.875", "0.0123", "0.0369", "*", "greater", "", "", "-1.91"}));
  EXPECT_EQ(rows[2][12], "") << "a NaN p-value is an empty cell";
  EXPECT_EQ(rows[2][9], "0.6666666667") << "10 significant digits";
  EXPECT_EQ(rows[4][2], "city");
  EXPECT_EQ(rows[4][3], "");
  EXPECT_EQ(rows[7][5], "reference");
  EXPECT_EQ(rows[7][6], "") << "no level";
}

TEST(AnalysisReport, ParticipantsCsvHasARowPerThresholdAndOneWithout) {
  TempDir dir("participants");
  AnalysisResult result = sample_result();
  result.participants.at(0).gaze_source = "tracker";  // P002's log names none: "not recorded"
  write_analysis_report(result, dir.path().string());
  const auto rows = parse_csv(read_text(dir.path() / "participants.csv"));
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"participant",
                                               "observer",
                                               "excluded",
                                               "session_ended",
                                               "complete_trials",
                                               "attention_checks",
                                               "attention_errors",
                                               "scene",
                                               "variant",
                                               "threshold",
                                               "note",
                                               "log_status",
                                               "latency_median_ms",
                                               "latency_p95_ms",
                                               "latency_refreshes",
                                               "dropped_frames",
                                               "present_clock",
                                               "practice_trials",
                                               "validation_attempts",
                                               "validations_passed",
                                               "validation_accuracy_deg",
                                               "validation_worst_accuracy_deg",
                                               "validation_precision_deg",
                                               "gaze_source",
                                               "refresh_hz",
                                               "frame_intervals",
                                               "frame_interval_median_ms",
                                               "frame_interval_sd_ms",
                                               "frame_interval_p99_ms",
                                               "frame_interval_max_ms",
                                               "frame_intervals_late",
                                               "frame_intervals_late_share"}));
  // P001's frame intervals: 16, 16, 16, 17, 34 ms at 60 Hz (34 is beyond 25 ms: late); SD by hand:
  // mean 19.8, squares 3 x 14.44 + 7.84 + 201.64 = 252.8, / 4 = 63.2.
  const std::vector<std::string> frames = {"60", "5",  "16", csv_number_for_test(std::sqrt(63.2)),
                                           "34", "34", "1",  "0.2"};
  EXPECT_EQ(rows[1], (std::vector<std::string>{"P001",
                                               "human",
                                               "false",
                                               "true",
                                               "120",
                                               "6",
                                               "0",
                                               kParkScene,
                                               "blur",
                                               "10",
                                               "",
                                               "sealed",
                                               "56.5",
                                               "73.25",
                                               "720",
                                               "3",
                                               "after_queue_present",
                                               "4",
                                               "3",
                                               "2",
                                               "0.5",
                                               "0.75",
                                               "0.125",
                                               "tracker"}) +
                         frames);
  EXPECT_EQ(rows[2], (std::vector<std::string>{"P001",
                                               "human",
                                               "false",
                                               "true",
                                               "120",
                                               "6",
                                               "0",
                                               "city",
                                               "",
                                               "",
                                               "every step answered correctly, censored",
                                               "sealed",
                                               "56.5",
                                               "73.25",
                                               "720",
                                               "3",
                                               "after_queue_present",
                                               "4",
                                               "3",
                                               "2",
                                               "0.5",
                                               "0.75",
                                               "0.125",
                                               "tracker"}) +
                         frames);
  // A study that validates nothing leaves the validation cells empty; no frame interval: empty numbers.
  EXPECT_EQ(rows[3], (std::vector<std::string>{"P002",
                                               "human",
                                               "true",
                                               "false",
                                               "80",
                                               "6",
                                               "4",
                                               "",
                                               "",
                                               "",
                                               "",
                                               "sealed",
                                               "",
                                               "",
                                               "",
                                               "1",
                                               "not recorded",
                                               "0",
                                               "",
                                               "",
                                               "",
                                               "",
                                               "",
                                               "not recorded",
                                               "",
                                               "0",
                                               "",
                                               "",
                                               "",
                                               "",
                                               "",
                                               ""}));
}

TEST(AnalysisReport, ThresholdsJsonHoldsTheResultWithNullForMissingNumbers) {
  TempDir dir("json");
  const AnalysisResult result = sample_result();
  write_analysis_report(result, dir.path().string());
  const json root = json::parse(read_text(dir.path() / "thresholds.json"));
  EXPECT_EQ(root["study"], "demo <study>");
  EXPECT_EQ(root["protocol"], "pair");
  EXPECT_EQ(root["question"], "");
  EXPECT_EQ(root["level_parameter"], "foveal_deg");
  EXPECT_EQ(root["higher_is_better"], true);
  EXPECT_EQ(root["levels"], json({5.0, 10.0, 20.0}));
  EXPECT_EQ(root["test"], json({{"kind", "exact binomial"},
                                {"null_proportion", 0.5},
                                {"alternative", "greater"},
                                {"alpha", 0.05},
                                {"correction", "holm"}}));
  EXPECT_EQ(root["guess_rate"], 0.5);
  EXPECT_EQ(root["guess_rate_source"], "attention checks (12 of 240)");
  EXPECT_EQ(root["inputs"].size(), 2u);

  ASSERT_EQ(root["thresholds"].size(), 2u);
  EXPECT_EQ(root["thresholds"][0]["scene"], kParkScene);
  EXPECT_EQ(root["thresholds"][0]["level"], 10.0);
  EXPECT_TRUE(root["thresholds"][0]["sd"].is_null());
  EXPECT_TRUE(root["thresholds"][1]["level"].is_null());
  EXPECT_EQ(root["thresholds"][1]["participants_without_threshold"], 1);

  ASSERT_EQ(root["fits"].size(), 1u);
  const json& fit = root["fits"][0];
  EXPECT_EQ(fit["shape"], "logistic");
  EXPECT_EQ(fit["rising"], false);
  EXPECT_EQ(fit["threshold"], 10.5);
  EXPECT_EQ(fit["slope"], 0.4);
  EXPECT_EQ(fit["lapse"], 0.02);
  EXPECT_EQ(fit["guess"], 0.5);
  EXPECT_EQ(fit["intervals"]["threshold"], json({{"lower", 8.0}, {"upper", 13.0}}));
  EXPECT_TRUE(fit["intervals"]["slope"]["lower"].is_null());
  EXPECT_TRUE(fit["intervals"]["slope"]["upper"].is_null());
  EXPECT_EQ(fit["deviance"], 1.25);
  EXPECT_EQ(fit["dof"], 0);
  EXPECT_TRUE(fit["deviance_p_value"].is_null());
  EXPECT_EQ(fit["log_likelihood"], -12.5);
  EXPECT_EQ(fit["converged"], true);
  EXPECT_EQ(fit["bootstrap_samples"], 998);
  EXPECT_EQ(fit["bootstrap_failures"], 2);
  ASSERT_EQ(fit["data"].size(), 3u);
  EXPECT_EQ(fit["data"][1], json({{"level", 10.0}, {"n", 12}, {"k_difference", 4}, {"proportion", 4.0 / 12.0}}));
  ASSERT_EQ(root["not_fitted"].size(), 1u);
  EXPECT_EQ(root["not_fitted"][0]["reason"], "weibull: did not converge");

  ASSERT_EQ(root["conditions"].size(), result.conditions.size());
  EXPECT_EQ(root["conditions"][0]["ci_upper"], 0.875);
  EXPECT_TRUE(root["conditions"][1]["p_value"].is_null());
  EXPECT_TRUE(root["conditions"][6]["level"].is_null());
  EXPECT_TRUE(root["conditions"][0]["mean_rating"].is_null());

  ASSERT_EQ(root["participants"].size(), 2u);
  EXPECT_EQ(root["participants"][0]["thresholds"].size(), 2u);
  EXPECT_EQ(root["participants"][0]["latency"], json({{"recorded", true},
                                                      {"median_ms", 56.5},
                                                      {"p95_ms", 73.25},
                                                      {"refreshes", 720},
                                                      {"dropped_frames", 3},
                                                      {"present_clock", "after_queue_present"}}));
  EXPECT_EQ(root["participants"][1]["latency"], json({{"recorded", false},
                                                      {"median_ms", nullptr},
                                                      {"p95_ms", nullptr},
                                                      {"refreshes", 0},
                                                      {"dropped_frames", 1},
                                                      {"present_clock", nullptr}}));
  EXPECT_TRUE(root["participants"][0]["thresholds"][1]["level"].is_null());
  EXPECT_EQ(root["participants"][1]["excluded"], true);
  EXPECT_EQ(root["participants"][1]["attention_errors"], 4);

  EXPECT_EQ(
      root["left_out"],
      json::array({{{"what", "results/demo/P003/events.jsonl"}, {"reason", "no complete trials (session log torn)"}}}));
}

TEST(AnalysisReport, RampAndSliderReportsHaveNoBinomialSections) {
  // Issue 18: slider and ramp reports printed the binomial test's text and empty fits and conditions
  // sections. Their thresholds are per participant: those sections are left out and the page says why.
  for (ProtocolKind kind : {ProtocolKind::ramp, ProtocolKind::slider}) {
    SCOPED_TRACE(int(kind));
    AnalysisResult result = sample_result();
    result.protocol = kind;
    result.conditions.clear();
    result.fits.clear();
    TempDir dir("per-participant");
    write_analysis_report(result, dir.path().string());
    const std::string html = read_text(dir.path() / "report.html");
    EXPECT_EQ(html.find("exact binomial"), std::string::npos);
    EXPECT_EQ(html.find("id=\"fits\""), std::string::npos);
    EXPECT_EQ(html.find("id=\"conditions\""), std::string::npos);
    EXPECT_EQ(html.find("Guess rate"), std::string::npos);
    EXPECT_NE(html.find("protocol has no per-condition tests or psychometric fits"), std::string::npos);
    EXPECT_NE(html.find("id=\"thresholds\""), std::string::npos);
  }
}

TEST(AnalysisReport, HtmlIsSelfContainedAndSaysEverything) {
  TempDir dir("html");
  write_analysis_report(sample_result(), dir.path().string());
  const std::string html = read_text(dir.path() / "report.html");
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.find("http"), std::string::npos) << "no external URL, not even the SVG namespace";
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_NE(html.find("<style>"), std::string::npos);
  // The test used, with its alternative.
  EXPECT_NE(html.find("exact binomial, one-sided (greater), H0 p = 1/2, Holm across levels, alpha 0.05"),
            std::string::npos);
  // Each table: headline (first), thresholds, fits, conditions, participants, frame intervals.
  EXPECT_EQ(count(html, "<table class=\"headline\">"), 1u);
  EXPECT_EQ(count(html, "<table>"), 5u);
  EXPECT_EQ(count(html, "</table>"), 6u);
  for (const char* id :
       {"id=\"thresholds\"", "id=\"fits\"", "id=\"conditions\"", "id=\"participants\"", "id=\"left-out\""}) {
    EXPECT_NE(html.find(id), std::string::npos) << id;
  }
  EXPECT_NE(html.find("<th>threshold CI</th>"), std::string::npos);
  EXPECT_NE(html.find("<td>[8, 13]</td>"), std::string::npos);
  EXPECT_NE(html.find("weibull: did not converge"), std::string::npos);
  EXPECT_NE(html.find("no complete trials (session log torn)"), std::string::npos);
  // Issue 18: practice trials and the eye-tracker validation per participant.
  EXPECT_NE(html.find("<td>120 (+4 practice)</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>2 / 3; 0.5 (0.75) deg, 0.125 deg</td>"), std::string::npos);
  EXPECT_NE(html.find("<td>none</td>"), std::string::npos);  // P002: no validation
  // Six plots, inline: share, psychometric, each participant's threshold, histogram, frame intervals
  // (the study's, P001's).
  EXPECT_EQ(count(html, "<svg "), 6u);
  EXPECT_EQ(count(html, "</svg>"), 6u);
  // Text escaped.
  EXPECT_NE(html.find("demo &lt;study&gt;"), std::string::npos);
  EXPECT_NE(html.find("park, &quot;north&quot;"), std::string::npos);
  EXPECT_EQ(html.find("<study>"), std::string::npos);
  EXPECT_EQ(html.find("\"north\""), std::string::npos);
  EXPECT_NE(html.find("1 included, 1 excluded"), std::string::npos);
  EXPECT_EQ(html.find("id=\"headset\""), std::string::npos) << "no headset session, no headset section";
}

// A headset session (issue 42) gets a section of its own: its runtime, each eye's size, field of
// view and pixels per degree, beside the present clock, refresh intervals, dropped frames, latency
// and tracker checks that a headset gives once for both eyes; thresholds.json has the same under
// the participant's "headset", and a desktop participant has none.
TEST(AnalysisReport, AHeadsetSessionShowsItsRuntimeAndEyesBesideItsTiming) {
  AnalysisResult result = sample_result();
  HeadsetSummary headset;
  headset.runtime = "fovlab test runtime 0.1.0";
  headset.eye_width_px = 64;
  headset.eye_height_px = 72;
  headset.view_model = "head-locked";
  headset.gaze_fixation = "fixation-distance";
  headset.fixation_distance_mm = 1500.0;
  headset.fov_deg[0] = std::array<double, 4>{-54.0, 49.0, 54.0, -56.0};
  headset.fov_deg[1] = std::array<double, 4>{-49.0, 54.0, 54.0, -56.0};
  headset.late_frames = 2;
  headset.gaze_refreshes = 80;  // 6 off the left eye's image, 2 without a gaze
  headset.gaze_off_image = {6, 0};
  headset.gaze_invalid_other = {2, 0};  // a schema 12 log: the right eye not marked
  result.participants.at(0).headset = headset;
  result.participants.at(0).present_clock = "openxr_predicted_display";
  TempDir dir("headset");
  write_analysis_report(result, dir.path().string());
  const std::string html = read_text(dir.path() / "report.html");
  EXPECT_EQ(count(html, "<h2 id=\"headset\">Headset</h2>"), 1u);
  // tan 49 + tan 54 = 2.5268 across 64 px: 0.442 px/deg at the view's centre.
  EXPECT_NE(html.find("<tr><td>P001</td><td>fovlab test runtime 0.1.0</td><td>64 x 72</td><td>[-54, 49, 54, -56] "
                      "deg, 0.442 x "),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td>[-49, 54, 54, -56] deg, 0.442 x "), std::string::npos);
  EXPECT_NE(html.find("<td>head-locked</td><td>fixation-distance (1500 mm)</td><td>openxr_predicted_display</td>"
                      "<td>5, median 16 ms, 1 late</td><td>3</td><td>2</td><td>56.5 / 73.25</td>"),
            std::string::npos)
      << html;
  EXPECT_EQ(html.find("<td>P002</td><td>fovlab test runtime"), std::string::npos) << "a desktop session: no row";
  // Gaze per eye: the left eye's shares as logged; the right eye's off-image refreshes are not logged.
  EXPECT_NE(html.find("<tr><td>P001</td><td>left</td><td>2.5% (2 of 80)</td><td>7.5% (6 of 80)</td><td>10% (8 of "
                      "80)</td><td>56.5 (both eyes)</td></tr>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<tr><td>P001</td><td>right</td><td>2.5% (2 of 80)</td><td>not logged</td><td>at least 10% "
                      "(8 of 80)</td><td>56.5 (both eyes)</td></tr>"),
            std::string::npos);
  EXPECT_EQ(html.find("<td>P002</td><td>left</td>"), std::string::npos) << "a desktop session: no gaze row";
  std::ifstream file(dir.path() / "thresholds.json");
  const nlohmann::json thresholds = nlohmann::json::parse(file);
  EXPECT_EQ(thresholds["participants"][0]["headset"],
            nlohmann::json::parse(R"({"runtime": "fovlab test runtime 0.1.0", "eye_width_px": 64, "eye_height_px": 72,
                "view_model": "head-locked", "gaze_fixation": "fixation-distance", "fixation_distance_mm": 1500.0,
                "eyes": [{"fov_deg": [-54.0, 49.0, 54.0, -56.0], "gaze_invalid_share": 0.025, "gaze_off_image_share": 0.075},
                         {"fov_deg": [-49.0, 54.0, 54.0, -56.0], "gaze_invalid_share": 0.025, "gaze_off_image_share": null}],
                "late_frames": 2, "gaze_refreshes": 80})"));
  EXPECT_FALSE(thresholds["participants"][1].contains("headset"));

  // Schema 13 marks the right eye's own: 9 off its image (the left's 6 among them), the same 2 without a gaze.
  result.participants.at(0).headset->right_eye_marked = true;
  result.participants.at(0).headset->gaze_off_image[1] = 9;
  result.participants.at(0).headset->gaze_invalid_other[1] = 2;
  TempDir marked("headset_marked");
  write_analysis_report(result, marked.path().string());
  const std::string marked_html = read_text(marked.path() / "report.html");
  EXPECT_NE(marked_html.find("<tr><td>P001</td><td>right</td><td>2.5% (2 of 80)</td><td>11.2% (9 of 80)</td><td>13.8% (11 "
                             "of 80)</td><td>56.5 (both eyes)</td></tr>"),
            std::string::npos)
      << marked_html;
  EXPECT_EQ(marked_html.find("before schema 13"), std::string::npos) << "no log in it lacks the right eye's marks";
  std::ifstream marked_file(marked.path() / "thresholds.json");
  const nlohmann::json right_eye = nlohmann::json::parse(marked_file)["participants"][0]["headset"]["eyes"][1];
  EXPECT_DOUBLE_EQ(right_eye.value("gaze_off_image_share", -1.0), 9.0 / 80.0) << right_eye;
  EXPECT_DOUBLE_EQ(right_eye.value("gaze_invalid_share", -1.0), 2.0 / 80.0) << right_eye;
}

TEST(AnalysisReport, PlotsShowTheirData) {
  TempDir dir("plots");
  AnalysisResult result = sample_result();
  result.participants[1].thresholds = {{result.fits[0].group, 20.0, ""}};  // excluded: not in the histogram
  result.headlines.clear();  // without headlines the first fit's interval is shaded (as before them)
  write_analysis_report(result, dir.path().string());
  for (const char* name : {"share_per_level.svg", "psychometric_park___north__blur.svg", "thresholds_histogram.svg"}) {
    const std::string svg = read_text(dir.path() / name);
    SCOPED_TRACE(name);
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0u);
    EXPECT_EQ(count(svg, "<svg"), 1u);
    EXPECT_EQ(count(svg, "</svg>"), 1u);
    std::string lower = svg;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    EXPECT_EQ(lower.find("nan"), std::string::npos);
  }
  const std::string share = read_text(dir.path() / "share_per_level.svg");
  EXPECT_EQ(count(share, "stroke-dasharray"), 1u);   // the line at 1/2
  EXPECT_EQ(count(share, "<circle"), 3u + 1u);       // the park group (plus its legend marker)
  EXPECT_EQ(count(share, "<rect x"), 1u + 3u + 1u);  // background, city's 3 square markers and its legend marker
  EXPECT_NE(share.find("park, &quot;north&quot;/blur"), std::string::npos);

  const std::string curve = read_text(dir.path() / "psychometric_park___north__blur.svg");
  EXPECT_EQ(count(curve, "<polyline"), 1u);             // the logistic
  EXPECT_EQ(count(curve, "fill-opacity=\"0.3\""), 2u);  // threshold band and its legend swatch
  EXPECT_NE(curve.find(">threshold CI (logistic)</text>"), std::string::npos);
  EXPECT_EQ(count(curve, "<circle"), 3u + 1u);  // 3 levels, legend

  const std::string histogram = read_text(dir.path() / "thresholds_histogram.svg");
  // One bar of height 1: P001's threshold (P002 is excluded).
  EXPECT_EQ(count(histogram, "font-size=\"11\">1</text>"), 1u);
  EXPECT_EQ(count(histogram, "font-size=\"11\">"), 1u);
}

TEST(AnalysisReport, PsychometricCurveFollowsTheModel) {
  TempDir dir("curve");
  AnalysisResult result = sample_result();
  result.fits[0].fits.push_back(logistic_fit(15.0));
  result.fits[0].fits.back().model.shape = PsychometricShape::cumulative_normal;
  write_analysis_report(result, dir.path().string());
  const std::string curve = read_text(dir.path() / "psychometric_park___north__blur.svg");
  EXPECT_EQ(count(curve, "<polyline"), 2u);  // one line per fit
  // 200 samples per curve.
  const auto at = curve.find("<polyline");
  const auto end = curve.find("/>", at);
  const std::string points = curve.substr(at, end - at);
  EXPECT_EQ(count(points, ","), 200u);
}

TEST(AnalysisReport, RatingStudyPlotsMeanRatingAgainstTheCutoff) {
  TempDir dir("rating");
  AnalysisResult result = sample_result();
  result.protocol = ProtocolKind::rating;
  result.alternative = Alternative::two_sided;
  result.fits.clear();
  for (ConditionRow& row : result.conditions) {
    row.mean_rating = 1.0 + 2.0 * row.proportion;
    row.sd_rating = 0.25;
  }
  for (ParticipantRow& participant : result.participants) participant.thresholds.clear();
  const auto names = file_names(write_analysis_report(result, dir.path().string()));
  EXPECT_EQ(names, (std::vector<std::string>{"headline.csv", "conditions.csv", "participants.csv", "thresholds.json",
                                             "share_per_level.svg", "frame_intervals.svg", "frame_intervals_P001.svg",
                                             "report.html"}));
  const std::string share = read_text(dir.path() / "share_per_level.svg");
  EXPECT_NE(share.find("mean rating"), std::string::npos);
  EXPECT_EQ(count(share, "stroke-dasharray"), 1u);  // the cutoff 2
  const std::string html = read_text(dir.path() / "report.html");
  EXPECT_NE(html.find("exact binomial, two-sided, H0 p = 1/2, Holm across levels, alpha 0.05"), std::string::npos);
  EXPECT_NE(html.find("<th>mean rating</th>"), std::string::npos);
  const auto rows = parse_csv(read_text(dir.path() / "conditions.csv"));
  EXPECT_EQ(rows[1][16], "1.5");
  EXPECT_EQ(rows[1][17], "0.25");
}

TEST(AnalysisReport, EmptyResultWritesTablesAndNoPlots) {
  TempDir dir("empty");
  const auto names = file_names(write_analysis_report(AnalysisResult{}, dir.path().string()));
  EXPECT_EQ(names, (std::vector<std::string>{"headline.csv", "conditions.csv", "participants.csv", "thresholds.json",
                                             "report.html"}));
  EXPECT_EQ(parse_csv(read_text(dir.path() / "headline.csv")).size(), 1u);
  EXPECT_EQ(parse_csv(read_text(dir.path() / "conditions.csv")).size(), 1u);
  EXPECT_EQ(parse_csv(read_text(dir.path() / "participants.csv")).size(), 1u);
  const json root = json::parse(read_text(dir.path() / "thresholds.json"));
  EXPECT_TRUE(root["fits"].empty());
  EXPECT_TRUE(root["left_out"].is_array());
  const std::string html = read_text(dir.path() / "report.html");
  EXPECT_NE(html.find("<p>nothing</p>"), std::string::npos);
  EXPECT_EQ(html.find("<svg"), std::string::npos);
}

TEST(AnalysisReport, PlotFileNamesAreSafeAndDistinct) {
  TempDir dir("names");
  AnalysisResult result = sample_result();
  GroupFit other = result.fits[0];
  other.group = {"park", "_\"north\"_blur"};  // sanitises to the same stem
  GroupFit odd = result.fits[0];
  odd.group = {"../../etc/x y", ""};
  result.fits = {result.fits[0], other, odd};
  const auto names = file_names(write_analysis_report(result, dir.path().string()));
  EXPECT_NE(std::find(names.begin(), names.end(), "psychometric_park___north__blur.svg"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "psychometric_park___north__blur_2.svg"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "psychometric_______etc_x_y.svg"), names.end());
  for (const std::string& name : names) {
    for (char c : name)
      EXPECT_TRUE(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.') << name;
  }
}

TEST(AnalysisReport, SameResultSameBytes) {
  TempDir a("same_a");
  TempDir b("same_b");
  const auto first = file_names(write_analysis_report(sample_result(), a.path().string()));
  const auto second = file_names(write_analysis_report(sample_result(), b.path().string()));
  ASSERT_EQ(first, second);
  for (const std::string& name : first) EXPECT_EQ(read_text(a.path() / name), read_text(b.path() / name)) << name;
}

TEST(AnalysisReport, HeadlineCsvHasOneRowPerGroupAndNoValueWhenNotEstimable) {
  TempDir dir("headline_csv");
  write_analysis_report(sample_result(), dir.path().string());
  const std::string text = read_text(dir.path() / "headline.csv");
  EXPECT_NE(text.find("\"park, \"\"north\"\"\""), std::string::npos) << "RFC 4180 quoting";
  const auto rows = parse_csv(text);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"scene",
                                               "variant",
                                               "quantity",
                                               "value",
                                               "lower",
                                               "upper",
                                               "status",
                                               "reason",
                                               "method",
                                               "aims_at",
                                               "flags",
                                               "participants",
                                               "paper_rule",
                                               "paper_value",
                                               "paper_difference",
                                               "paper_rule_is_headline",
                                               "pooled_fit",
                                               "pooled_fit_lower",
                                               "pooled_fit_upper",
                                               "notes"}));
  EXPECT_EQ(rows[1], (std::vector<std::string>{kParkScene,
                                               "blur",
                                               "threshold",
                                               "12.5",
                                               "11.75",
                                               "13.25",
                                               "estimated",
                                               "",
                                               "mean over participants, 95 % Student-t interval",
                                               "the participants' mean threshold",
                                               "lapse at its bound (0); slope at its bound",
                                               "8",
                                               "Polychronakis et al. 2021, 4.7",
                                               "16",
                                               "the walk reports the last level not distinguished, not the crossing",
                                               "false",
                                               "",
                                               "",
                                               "",
                                               "2 participants censored at the best level"}));
  // Not estimable: the value, lower and upper cells are empty although the struct holds numbers.
  EXPECT_EQ(rows[2], (std::vector<std::string>{"city",
                                               "",
                                               "threshold",
                                               "",
                                               "",
                                               "",
                                               "not estimable",
                                               "the fit's threshold -55.333 lies outside the tested levels 4 to 64",
                                               "logistic fit, 95 % profile-likelihood interval",
                                               "the level where p_see = 1/2",
                                               "",
                                               "3",
                                               "",
                                               "",
                                               "",
                                               "false",
                                               "14.5",
                                               "13",
                                               "16.25",
                                               ""}));
}

TEST(AnalysisReport, ThresholdsJsonHoldsEachHeadlineAndTheFrameIntervals) {
  TempDir dir("headline_json");
  write_analysis_report(sample_result(), dir.path().string());
  const json root = json::parse(read_text(dir.path() / "thresholds.json"));
  ASSERT_EQ(root["headlines"].size(), 2u);
  const json& park = root["headlines"][0];
  EXPECT_EQ(park["scene"], kParkScene);
  EXPECT_EQ(park["variant"], "blur");
  EXPECT_EQ(park["quantity"], "threshold");
  EXPECT_EQ(park["value"], 12.5);
  EXPECT_EQ(park["interval"], json({{"lower", 11.75}, {"upper", 13.25}}));
  EXPECT_EQ(park["status"], "estimated");
  EXPECT_EQ(park["reason"], "");
  EXPECT_EQ(park["method"], "mean over participants, 95 % Student-t interval");
  EXPECT_EQ(park["aims_at"], "the participants' mean threshold");
  EXPECT_EQ(park["flags"], json({"lapse at its bound (0)", "slope at its bound"}));
  EXPECT_EQ(park["notes"], json({"2 participants censored at the best level"}));
  EXPECT_EQ(park["participants"], 8);
  EXPECT_EQ(park["paper_rule"], "Polychronakis et al. 2021, 4.7");
  EXPECT_EQ(park["paper_value"], 16.0);
  EXPECT_EQ(park["paper_rule_is_headline"], false);
  EXPECT_TRUE(park["pooled_fit"].is_null());
  const json& city = root["headlines"][1];
  EXPECT_EQ(city["status"], "not estimable");
  EXPECT_TRUE(city["value"].is_null());
  EXPECT_TRUE(city["interval"]["lower"].is_null());
  EXPECT_TRUE(city["interval"]["upper"].is_null());
  EXPECT_EQ(city["reason"], "the fit's threshold -55.333 lies outside the tested levels 4 to 64");
  EXPECT_EQ(city["pooled_fit"], json({{"value", 14.5}, {"interval", {{"lower", 13.0}, {"upper", 16.25}}}}));
  // Frame intervals: P001's, and the study's (the included participants pooled: P001 alone).
  const json& frames = root["participants"][0]["frame_intervals"];
  EXPECT_EQ(frames["refresh_hz"], 60.0);
  EXPECT_DOUBLE_EQ(frames["late_beyond_ms"].get<double>(), 25.0);
  EXPECT_EQ(frames["intervals"], 5);
  EXPECT_EQ(frames["median_ms"], 16.0);
  EXPECT_EQ(frames["p99_ms"], 34.0);
  EXPECT_EQ(frames["max_ms"], 34.0);
  EXPECT_EQ(frames["late"], 1);
  EXPECT_EQ(frames["late_share"], 0.2);
  EXPECT_NEAR(frames["sd_ms"].get<double>(), std::sqrt(63.2), 1e-12);
  EXPECT_EQ(root["frame_intervals"], frames);
  EXPECT_TRUE(root["participants"][1]["frame_intervals"]["median_ms"].is_null());
}

TEST(AnalysisReport, HeadlineTableComesFirstAndPrintsNoNumberWhenNotEstimable) {
  TempDir dir("headline_html");
  write_analysis_report(sample_result(), dir.path().string());
  const std::string html = read_text(dir.path() / "report.html");
  const auto headline = html.find("<h2 id=\"headline\">");
  ASSERT_NE(headline, std::string::npos);
  EXPECT_EQ(headline, html.find("<h2"));  // the first section, before the study's
  EXPECT_LT(headline, html.find("<h2 id=\"summary\">"));
  EXPECT_LT(html.find("<table class=\"headline\">"), html.find("<table>"));
  const std::string table = html.substr(headline, html.find("</table>", headline) - headline);
  EXPECT_NE(table.find("12.5 [11.75, 13.25]"), std::string::npos);
  EXPECT_NE(table.find("lapse at its bound (0); slope at its bound"), std::string::npos);
  EXPECT_NE(table.find("Polychronakis et al. 2021, 4.7: 16<br>the walk reports"), std::string::npos);
  // The not estimable row: its status and reason, and none of the numbers its struct holds.
  EXPECT_NE(table.find("<tr class=\"not-estimable\">"), std::string::npos);
  EXPECT_NE(table.find("not estimable</span>: the fit&apos;s threshold -55.333 lies outside"), std::string::npos);
  EXPECT_EQ(table.find("5.12"), std::string::npos);
  // The definition once, above the thresholds table; plain column names.
  EXPECT_EQ(count(html, "the smallest level from which every larger level is judged identical"), 1u);
  EXPECT_NE(html.find("<th>participants with a threshold</th>"), std::string::npos);
  EXPECT_NE(html.find("<th>participants without</th>"), std::string::npos);
  EXPECT_EQ(html.find("participants with 0"), std::string::npos);
}

TEST(AnalysisReport, NoStarsOnTwoSidedRowsTheThresholdDoesNotCountAsDistinguished) {
  AnalysisResult result = sample_result();
  result.alternative = Alternative::two_sided;
  for (ConditionRow& row : result.conditions) row.stars = "**";
  TempDir dir("stars");
  write_analysis_report(result, dir.path().string());
  const auto rows = parse_csv(read_text(dir.path() / "conditions.csv"));
  // park: 3 of 12 (below 1/2: distinguished, starred), 8 and 12 of 12 (favoured: no stars).
  EXPECT_EQ(rows[1][14], "**");
  EXPECT_EQ(rows[2][14], "");
  EXPECT_EQ(rows[3][14], "");
  EXPECT_EQ(rows[5][14], "") << "6 of 12 is not below 1/2";
  const json root = json::parse(read_text(dir.path() / "thresholds.json"));
  EXPECT_EQ(root["conditions"][0]["stars"], "**");
  EXPECT_EQ(root["conditions"][2]["stars"], "");
  const std::string html = read_text(dir.path() / "report.html");
  EXPECT_EQ(count(html, "<td>**</td>"), 1u);
  // One-sided: the alternative names the direction; the stars stay.
  result.alternative = Alternative::greater;
  TempDir one_sided("stars_greater");
  write_analysis_report(result, one_sided.path().string());
  const auto greater = parse_csv(read_text(one_sided.path() / "conditions.csv"));
  EXPECT_EQ(greater[3][14], "**");
}

TEST(AnalysisReport, PlotsMarkTheHeadlineAndOverlayVariants) {
  AnalysisResult result = sample_result();
  GroupFit sharp = result.fits[0];
  sharp.group = {kParkScene, "sharp"};
  result.fits.push_back(sharp);
  Headline sharp_headline = estimated_headline(sharp.group);
  sharp_headline.value = 9.0;
  result.headlines.push_back(sharp_headline);
  TempDir dir("overlay");
  const auto names = file_names(write_analysis_report(result, dir.path().string()));
  // The scene's two variants on one plot, named by the scene.
  EXPECT_NE(std::find(names.begin(), names.end(), "psychometric_park___north_.svg"), names.end());
  EXPECT_EQ(std::find(names.begin(), names.end(), "psychometric_park___north__blur.svg"), names.end());
  const std::string svg = read_text(dir.path() / "psychometric_park___north_.svg");
  EXPECT_NE(svg.find(">blur: data</text>"), std::string::npos);
  EXPECT_NE(svg.find(">sharp: data</text>"), std::string::npos);
  EXPECT_EQ(count(svg, "<polyline"), 2u);  // one curve a variant
  // Each headline: a dashed vertical line (plus its legend sample) and its interval as a band.
  EXPECT_EQ(count(svg, "stroke-dasharray=\"4 3\""), 4u);
  EXPECT_NE(svg.find("blur: headline 12.5 [11.75, 13.25]"), std::string::npos);
  EXPECT_EQ(count(svg, "fill-opacity=\"0.18\""), 2u);
  // Each participant's threshold as a point, the headline marked.
  const std::string points = read_text(dir.path() / "participant_thresholds_park___north_.svg");
  EXPECT_NE(points.find(">P001</text>"), std::string::npos);
  EXPECT_NE(points.find("headline 12.5 [11.75, 13.25]"), std::string::npos);
}

}  // namespace
}  // namespace fovlab::analysis
