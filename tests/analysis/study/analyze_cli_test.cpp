// `fovlab analyze` end to end (docs/analysis.md, "From logs to a study" and "Outputs"): every
// protocol's simulated sessions analysed into thresholds.json, conditions.csv, participants.csv and
// report.html; bad input (a torn line, another schema version, logs of different studies, a
// duplicate participant, an edited log, an excluded participant, nothing analysable, bad flags)
// reported with its reason, what can still be analysed analysed, and the logs never modified; the
// test's alternative named in the outputs; and the output folder written as a set (never a mix of
// two analyses, never outside results/ for a study name of a log header, never a participant's).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/config/study_config.h"
#include "study/log/event_log.h"
#include "study/schedule/study_plan.h"
#include "tests/app/cli_test_support.h"
#include "tests/support/forged_log.h"
#include "tests/support/temp_dir.h"

namespace {

namespace fs = std::filesystem;
using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using nlohmann::json;

// Sessions are headless whatever the machine has.
CommandResult fovlab_command(const std::string& arguments) {
  return fovlab::cli_test::run(arguments, "env -u DISPLAY -u WAYLAND_DISPLAY");
}

fs::path scratch(const std::string& name) { return fovlab::cli_test::scratch("fovlab-analyze-cli-" + name); }

std::string fixture(const std::string& name) {
  return (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies" / (name + ".toml")).string();
}

// A variant of a fixture study written to `folder`: each (from, to) replaced once, and the
// fixture's relative scene path made absolute so the copy runs from anywhere.
fs::path write_variant(const fs::path& folder, const std::string& name, const std::string& from_fixture,
                       const std::vector<std::pair<std::string, std::string>>& replacements) {
  std::string text = read_all(fixture(from_fixture));
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from << " not in " << from_fixture;
    if (at != std::string::npos) text.replace(at, from.size(), to);
  };
  const std::string scene = (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/scenes/sphere.glsl").string();
  replace("\"../scenes/sphere.glsl\"", '"' + scene + '"');
  for (const auto& [from, to] : replacements) replace(from, to);
  const fs::path path = folder / (name + ".toml");
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// One simulated session; its log is results/<study>/<participant>/events.jsonl.
void run_session(const std::string& config, const std::string& participant, const fs::path& results,
                 const std::string& observer = "simulated") {
  const CommandResult run = fovlab_command("run " + config + " --participant " + participant +
                                           " --headless --results " + results.string() + " --observer " + observer);
  ASSERT_EQ(run.exit_code, 0) << config << " " << participant << ": " << run.err;
}

CommandResult analyze(const std::string& arguments) { return fovlab_command("analyze " + arguments); }

// Every file under a folder and its bytes: the logs before and after an analysis.
std::map<std::string, std::string> snapshot(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file()) files[entry.path().string()] = read_all(entry.path());
  return files;
}

void expect_unchanged(const std::map<std::string, std::string>& before, const fs::path& folder) {
  const std::map<std::string, std::string> after = snapshot(folder);
  EXPECT_EQ(after.size(), before.size()) << "files were added to or removed from " << folder;
  for (const auto& [path, bytes] : before) {
    const auto found = after.find(path);
    ASSERT_NE(found, after.end()) << path << " was removed";
    EXPECT_TRUE(found->second == bytes) << path << " was modified";
  }
}

json load_json(const fs::path& path) {
  const std::string text = read_all(path);
  const json parsed = json::parse(text, nullptr, /*allow_exceptions=*/false);
  EXPECT_FALSE(parsed.is_discarded()) << path << " is not JSON";
  return parsed.is_discarded() ? json::object() : parsed;
}

// The reasons `left_out` gives for items whose `what` contains `what`.
std::vector<std::string> left_out_reasons(const json& thresholds, const std::string& what) {
  std::vector<std::string> reasons;
  for (const json& item : thresholds.value("left_out", json::array()))
    if (item.value("what", "").find(what) != std::string::npos) reasons.push_back(item.value("reason", ""));
  return reasons;
}

std::string joined(const std::vector<std::string>& texts) {
  std::string all;
  for (const std::string& text : texts) all += text + " | ";
  return all;
}

// The report's "Left out" section (to the end of the page).
std::string html_left_out(const fs::path& out) {
  const std::string html = read_all(out / "report.html");
  const size_t at = html.find("<h2 id=\"left-out\">");
  EXPECT_NE(at, std::string::npos) << "report.html has no Left out section";
  return at == std::string::npos ? std::string() : html.substr(at);
}

// `what` is listed in thresholds.json's left_out with a reason containing `reason`, and the report's
// Left out section names it with that reason.
void expect_left_out(const fs::path& out, const std::string& what, const std::string& reason) {
  const json thresholds = load_json(out / "thresholds.json");
  const std::vector<std::string> reasons = left_out_reasons(thresholds, what);
  ASSERT_FALSE(reasons.empty()) << what << " is not in left_out: " << thresholds["left_out"].dump();
  EXPECT_TRUE(std::any_of(reasons.begin(), reasons.end(),
                          [&](const std::string& r) { return r.find(reason) != std::string::npos; }))
      << what << ": " << joined(reasons) << " does not say " << reason;
  const std::string section = html_left_out(out);
  EXPECT_NE(section.find(what), std::string::npos) << "report.html's Left out does not name " << what << ":\n"
                                                   << section;
  bool with_reason = false;
  for (size_t named = section.find(what); named != std::string::npos; named = section.find(what, named + 1)) {
    const size_t item_end = section.find("</li>", named);
    with_reason = with_reason || section.substr(named, item_end - named).find(reason) != std::string::npos;
  }
  EXPECT_TRUE(with_reason) << "report.html's Left out gives " << what << " no reason with " << reason << ":\n"
                           << section;
}

std::vector<std::string> participants_of(const json& thresholds) {
  std::vector<std::string> ids;
  for (const json& participant : thresholds.value("participants", json::array()))
    ids.push_back(participant.value("participant", ""));
  return ids;
}

// The data rows of a CSV file, split at commas (the tests only read columns before any quoted one).
std::vector<std::vector<std::string>> csv_rows(const fs::path& path) {
  std::istringstream text(read_all(path));
  std::vector<std::vector<std::string>> rows;
  std::string line;
  bool header = true;
  while (std::getline(text, line)) {
    if (header) {
      header = false;
      continue;
    }
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream cells_text(line);
    while (std::getline(cells_text, cell, ',')) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

// tiny_2afc sessions of P001..P00n under results/tiny_2afc.
void run_2afc_participants(const fs::path& results, int count) {
  for (int i = 1; i <= count; ++i) run_session(fixture("tiny_2afc"), "P00" + std::to_string(i), results);
}

fs::path log_of(const fs::path& results, const std::string& study, const std::string& participant) {
  return results / study / participant / "events.jsonl";
}

// ---------------------------------------------------------------------------------------------

struct ProtocolCase {
  const char* fixture;
  const char* study;
  const char* protocol;
};

TEST(AnalyzeCli, EveryProtocolEndToEnd) {
  const ProtocolCase cases[] = {{"tiny_2afc", "tiny_2afc", "2afc"},
                                {"pair", "tiny_pair", "pair"},
                                {"ramp", "tiny_ramp", "ramp"},
                                {"slider", "tiny_slider", "slider"},
                                {"rating", "tiny_rating", "rating"}};
  for (const ProtocolCase& c : cases) {
    SCOPED_TRACE(c.fixture);
    const fs::path results = scratch("protocols") / c.fixture;
    run_session(fixture(c.fixture), "P001", results);
    run_session(fixture(c.fixture), "P002", results);
    ASSERT_FALSE(testing::Test::HasFatalFailure());
    const auto before = snapshot(results);
    const fs::path out = scratch("protocols") / (std::string(c.fixture) + "-out");

    const CommandResult result = analyze((results / c.study).string() + " --bootstrap 20 --out " + out.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_TRUE(result.err.empty()) << result.err;
    for (const char* file : {"thresholds.json", "conditions.csv", "participants.csv", "report.html"})
      EXPECT_TRUE(fs::is_regular_file(out / file)) << file;
    expect_unchanged(before, results);

    const json thresholds = load_json(out / "thresholds.json");
    EXPECT_EQ(thresholds.value("study", ""), c.study);
    EXPECT_EQ(thresholds.value("protocol", ""), c.protocol);
    EXPECT_EQ(thresholds["test"].value("alternative", ""), "two-sided");
    EXPECT_EQ(thresholds["inputs"].size(), 2u) << thresholds["inputs"].dump();
    EXPECT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P002"}));
    for (const json& participant : thresholds["participants"]) {
      EXPECT_FALSE(participant.value("excluded", true));
      EXPECT_TRUE(participant.value("session_ended", false));
      EXPECT_GT(participant.value("complete_trials", 0), 0);
    }
    EXPECT_TRUE(thresholds["left_out"].empty()) << thresholds["left_out"].dump();
    ASSERT_FALSE(thresholds["thresholds"].empty());

    const std::string protocol = c.protocol;
    const bool per_participant = protocol == "pair" || protocol == "ramp" || protocol == "slider";
    if (per_participant) {
      // Every participant has a threshold per group, and the study's per-participant thresholds
      // (pair also has pooled ones) average them.
      for (const json& participant : thresholds["participants"]) {
        ASSERT_FALSE(participant["thresholds"].empty()) << participant.dump();
        for (const json& threshold : participant["thresholds"])
          EXPECT_TRUE(threshold["level"].is_number()) << participant.dump();
      }
      size_t across_participants = 0;
      for (const json& threshold : thresholds["thresholds"]) {
        if (threshold.value("definition", "").find("per participant") == std::string::npos) continue;
        ++across_participants;
        EXPECT_TRUE(threshold["level"].is_number()) << threshold.dump();
        EXPECT_TRUE(threshold["mean"].is_number()) << threshold.dump();
        EXPECT_EQ(threshold.value("participants_with_threshold", 0), 2) << threshold.dump();
      }
      EXPECT_EQ(across_participants, thresholds["participants"][0]["thresholds"].size());
      // participants.csv: a row per participant and group, each with its threshold.
      const auto rows = csv_rows(out / "participants.csv");
      ASSERT_FALSE(rows.empty());
      for (const auto& row : rows) {
        ASSERT_GE(row.size(), 10u) << row.front();
        EXPECT_EQ(row[1], "simulated") << "participants.csv: the observer of " << row[0];
        EXPECT_FALSE(row[9].empty()) << "participants.csv: no threshold for " << row[0] << " " << row[7];
      }
    }
    if (protocol == "2afc" || protocol == "pair" || protocol == "rating") {
      // Comparison protocols: conditions with trials, and a threshold per group.
      ASSERT_FALSE(thresholds["conditions"].empty());
      for (const json& condition : thresholds["conditions"]) {
        EXPECT_GT(condition.value("n", 0), 0) << condition.dump();
        EXPECT_LE(condition.value("k", 0), condition.value("n", 0)) << condition.dump();
      }
      for (const json& threshold : thresholds["thresholds"])
        EXPECT_FALSE(threshold.value("definition", "").empty()) << threshold.dump();
      if (protocol == "rating") {
        for (const json& condition : thresholds["conditions"]) EXPECT_TRUE(condition["mean_rating"].is_number());
      }
    }
    // conditions.csv: the JSON's rows, each with n >= k (n column 7, k column 8).
    const auto rows = csv_rows(out / "conditions.csv");
    EXPECT_EQ(rows.size(), thresholds["conditions"].size());
    for (const auto& row : rows) {
      ASSERT_GE(row.size(), 9u);
      EXPECT_EQ(row[1], protocol);
      EXPECT_EQ(row[4], "ipr") << "method of the test stimuli";
      EXPECT_GE(std::stoull(row[7]), std::stoull(row[8])) << "n < k in " << row[5];
      EXPECT_GT(std::stoull(row[7]), 0u) << row[5];
    }

    const std::string html = read_all(out / "report.html");
    EXPECT_NE(html.find("fovlab analysis: " + std::string(c.study)), std::string::npos);
    // Ramps and sliders have no binomial tests (issue 18: their reports no longer print one).
    const bool per_participant_only = protocol == "ramp" || protocol == "slider";
    EXPECT_EQ(html.find("two-sided") != std::string::npos, !per_participant_only);
    EXPECT_NE(html_left_out(out).find("<p>nothing</p>"), std::string::npos) << html_left_out(out);
    EXPECT_NE(result.out.find("study " + std::string(c.study)), std::string::npos) << result.out;

    // Each threshold cites the paper its definition comes from by authors and year (the full
    // reference: docs/references.md), and no output names a paper by a seed number (issue 38).
    const std::string paper = protocol == "2afc"     ? "Polychronakis et al. 2023, "
                              : protocol == "rating" ? "Ye et al. 2022, "
                                                     : "Polychronakis et al. 2021, ";
    for (const json& threshold : thresholds["thresholds"]) {
      EXPECT_EQ(threshold.value("definition", "").rfind(paper, 0), 0u) << threshold.dump();
      EXPECT_NE(html.find(paper), std::string::npos) << "report.html does not cite " << paper;
    }
    // The report's References section gives that paper in full.
    const std::string title = protocol == "2afc"     ? "An Inverted Pyramid Acceleration Structure"
                              : protocol == "rating" ? "Rectangular Mapping-based Foveated Rendering"
                                                     : "Emulating Foveated Path Tracing";
    const size_t references = html.find("<h2 id=\"references\">References</h2>");
    ASSERT_NE(references, std::string::npos);
    EXPECT_NE(html.find(title, references), std::string::npos) << html.substr(references);
    for (const char* file : {"thresholds.json", "conditions.csv", "participants.csv", "report.html"})
      EXPECT_EQ(read_all(out / file).find("eed 00"), std::string::npos) << file << " cites a paper by seed number";
    EXPECT_EQ(result.out.find("eed 00"), std::string::npos) << result.out;
  }
}

// A crash's torn last line: not read, the complete trials before it are, and both are listed.
TEST(AnalyzeCli, TornLastLineIsListedAndTheLogStillAnalysed) {
  const fs::path results = scratch("torn") / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path torn = log_of(results, "tiny_2afc", "P001");
  const int trials_before = [&] {
    const fs::path out = scratch("torn") / "out-intact";
    const CommandResult intact = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
    EXPECT_EQ(intact.exit_code, 0) << intact.err;
    return load_json(out / "thresholds.json")["participants"][0].value("complete_trials", -1);
  }();
  ASSERT_GT(trials_before, 0);
  std::ofstream(torn, std::ios::binary | std::ios::app) << "{\"attention_check\":false,\"block\":1,\"chain\":\"12";

  // P002: cut in the middle of a trial's line, as a crash leaves it (a started trial, a torn line).
  const fs::path cut = log_of(results, "tiny_2afc", "P002");
  std::string text = read_all(cut);
  const size_t trial_start = text.rfind("\"event\":\"trial_start\"");
  ASSERT_NE(trial_start, std::string::npos);
  const size_t response = text.find("\"event\":\"response\"", trial_start);
  ASSERT_NE(response, std::string::npos);
  std::ofstream(cut, std::ios::binary | std::ios::trunc) << text.substr(0, response);

  const auto before = snapshot(results);
  const fs::path out = scratch("torn") / "out";
  const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_unchanged(before, results);
  const json thresholds = load_json(out / "thresholds.json");
  EXPECT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P002"}));
  EXPECT_EQ(thresholds["participants"][0].value("complete_trials", -1), trials_before);
  EXPECT_LT(thresholds["participants"][1].value("complete_trials", -1), trials_before);
  expect_left_out(out, torn.string(), "cut off");
  expect_left_out(out, cut.string(), "cut off");
  expect_left_out(out, cut.string(), "not finished");
  EXPECT_NE(result.out.find("cut off"), std::string::npos) << result.out;
  EXPECT_FALSE(thresholds["conditions"].empty());
}

// A log of a schema version this build does not read is left out, naming the version.
TEST(AnalyzeCli, UnknownSchemaVersionIsLeftOutOthersAnalysed) {
  const fs::path results = scratch("schema") / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path copy = results / "tiny_2afc" / "P003" / "events.jsonl";
  fs::create_directories(copy.parent_path());
  std::string text = read_all(log_of(results, "tiny_2afc", "P002"));
  const size_t first_line_end = text.find('\n');
  const size_t version = text.find("\"schema_version\":");
  ASSERT_LT(version, first_line_end);
  const size_t value = version + std::string("\"schema_version\":").size();
  text.replace(value, text.find_first_not_of("0123456789", value) - value, "99");
  // Another participant ID, so only the schema version is wrong with it.
  const size_t participant = text.find("\"participant\":\"P002\"");
  ASSERT_LT(participant, text.find('\n'));
  text.replace(participant, std::string("\"participant\":\"P002\"").size(), "\"participant\":\"P003\"");
  std::ofstream(copy, std::ios::binary) << text;

  const auto before = snapshot(results);
  const fs::path out = scratch("schema") / "out";
  const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_unchanged(before, results);
  const json thresholds = load_json(out / "thresholds.json");
  EXPECT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P002"}));
  const std::string reasons = joined(left_out_reasons(thresholds, copy.string()));
  EXPECT_TRUE(reasons.find("schema_version 99") != std::string::npos || reasons.find("chain") != std::string::npos)
      << reasons;
  expect_left_out(out, copy.string(), reasons.find("schema_version") != std::string::npos ? "schema_version" : "chain");
}

// Logs of several studies (a results folder of three studies, say) are refused, naming each study
// with its count of logs, and nothing is written; each study's own folder is analysed.
TEST(AnalyzeCli, LogsOfSeveralStudiesAreRefusedNamingEach) {
  const fs::path results = scratch("mixed") / "results";
  run_session(fixture("tiny_2afc"), "P001", results);
  run_session(fixture("rating"), "P001", results);
  run_session(fixture("rating"), "P002", results);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const auto before = snapshot(results);
  const fs::path out = scratch("mixed") / "out";
  const CommandResult result = analyze(results.string() + " --bootstrap 0 --out " + out.string());
  expect_one_line_error(result, "session logs of 2 studies (tiny_rating 2, tiny_2afc 1 logs)");
  EXPECT_NE(result.err.find(results.string()), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(out));
  expect_unchanged(before, results);
  // Each study's folder on its own.
  for (const char* study : {"tiny_2afc", "tiny_rating"}) {
    const fs::path study_out = scratch("mixed") / (std::string(study) + "-out");
    const CommandResult one = analyze((results / study).string() + " --bootstrap 0 --out " + study_out.string());
    ASSERT_EQ(one.exit_code, 0) << one.err;
    EXPECT_EQ(load_json(study_out / "thresholds.json").value("study", ""), study);
  }
}

// The session at `log` as if a person had answered it: the header's observer set to "human" (and its
// participant ID to `participant`, when given) and the chain made whole again (what the header says
// is all the analysis goes by).
void as_human_session(const fs::path& log) {
  std::vector<std::string> lines = fovlab::testing::lines_of(read_all(log));
  json header = json::parse(lines.front());
  header["observer"] = "human";
  lines.front() = header.dump();
  std::ofstream(log, std::ios::binary | std::ios::trunc) << fovlab::testing::rechained(lines);
}

// Simulated observers never mix with real participants unless asked: a study with both is refused
// with the counts; --observers human or simulated takes one kind (the other listed as left out),
// --observers all pools them and says so; the observer is a column of participants.csv and
// trials.csv, and a field of thresholds.json.
TEST(AnalyzeCli, HumanAndSimulatedSessionsNeverMixSilently) {
  const fs::path results = scratch("observers") / "results";
  run_2afc_participants(results, 3);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  as_human_session(log_of(results, "tiny_2afc", "P002"));
  const auto before = snapshot(results);
  const fs::path study = results / "tiny_2afc";
  const fs::path out = scratch("observers") / "out";
  expect_one_line_error(analyze(study.string() + " --bootstrap 0 --out " + out.string()),
                        "study tiny_2afc: 1 human and 2 simulated session(s)");
  EXPECT_FALSE(fs::exists(out));
  expect_one_line_error(analyze(study.string() + " --observers robots --out " + out.string()), "--observers");

  const struct {
    const char* filter;
    std::vector<std::string> participants;
    const char* observers;
    const char* headline;
  } cases[] = {
      {"human", {"P002"}, "human", "1 participant(s), "},
      {"simulated", {"P001", "P003"}, "simulated", "2 participant(s) (simulated observers)"},
      {"all", {"P001", "P002", "P003"}, "human and simulated", "3 participant(s) (human and simulated observers)"}};
  for (const auto& c : cases) {
    const fs::path filtered = scratch("observers") / (std::string("out-") + c.filter);
    const CommandResult result =
        analyze(study.string() + " --bootstrap 0 --observers " + c.filter + " --out " + filtered.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find(c.headline), std::string::npos) << result.out;
    const json thresholds = load_json(filtered / "thresholds.json");
    EXPECT_EQ(participants_of(thresholds), c.participants) << c.filter;
    EXPECT_EQ(thresholds.value("observers", ""), c.observers);
    for (const json& participant : thresholds["participants"])
      EXPECT_EQ(participant.value("observer", ""),
                participant.value("participant", "") == "P002" ? "human" : "simulated");
    const std::string csv = read_all(filtered / "participants.csv");
    EXPECT_EQ(csv.rfind("participant,observer,", 0), 0u) << csv;
    if (std::string(c.filter) == "human") {
      EXPECT_NE(csv.find("P002,human,"), std::string::npos) << csv;
      expect_left_out(filtered, log_of(results, "tiny_2afc", "P001").string(), "answered by a simulated observer");
    }
  }
  expect_one_line_error(
      analyze(log_of(results, "tiny_2afc", "P001").string() + " --observers human --out " + out.string()),
      "no session answered by a human observer");
  EXPECT_FALSE(fs::exists(out));
  // The observers are taken before duplicate IDs are looked at: a human session whose ID a simulated
  // one (first in path order) also has is analysed with --observers human, not left out as a duplicate.
  const fs::path elsewhere = scratch("observers") / "elsewhere";
  run_session(fixture("tiny_2afc"), "P001", elsewhere);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path twin = study / "P009";
  fs::copy(elsewhere / "tiny_2afc" / "P001", twin, fs::copy_options::recursive);
  as_human_session(twin / "events.jsonl");
  const fs::path twin_out = scratch("observers") / "out-twin";
  const CommandResult twin_result =
      analyze(study.string() + " --bootstrap 0 --observers human --out " + twin_out.string());
  ASSERT_EQ(twin_result.exit_code, 0) << twin_result.err;
  const json twin_thresholds = load_json(twin_out / "thresholds.json");
  EXPECT_EQ(participants_of(twin_thresholds), (std::vector<std::string>{"P002", "P001"}));
  EXPECT_EQ(twin_thresholds["participants"][1].value("log_path", ""), (twin / "events.jsonl").string());
  fs::remove_all(twin);
  // trials.csv says who answered each row.
  const fs::path trials = scratch("observers") / "trials.csv";
  ASSERT_EQ(fovlab_command("export " + study.string() + " --out " + trials.string()).exit_code, 0);
  const std::string csv = read_all(trials);
  EXPECT_EQ(csv.rfind("study,participant,observer,protocol,", 0), 0u) << csv.substr(0, 200);
  EXPECT_NE(csv.find("tiny_2afc,P002,human,"), std::string::npos);
  EXPECT_NE(csv.find("tiny_2afc,P001,simulated,"), std::string::npos);
  expect_unchanged(before, results);
}

// A session's gaze source as a window session would have logged it (a tracker's, or the mouse's).
void with_gaze_source(const fs::path& log, const std::string& kind, const std::string& spec) {
  std::vector<std::string> lines = fovlab::testing::lines_of(read_all(log));
  json header = json::parse(lines.front());
  header["gaze"] = spec;
  header["gaze_source"] = {{"kind", kind}, {"spec", spec}, {"requested", true}, {"require", json::array()}};
  lines.front() = header.dump();
  std::ofstream(log, std::ios::binary | std::ios::trunc) << fovlab::testing::rechained(lines);
}

// The last cell of each participants.csv row (gaze_source), by participant.
// participant -> its gaze_source cell (the column found by its header).
std::map<std::string, std::string> gaze_sources_of(const fs::path& participants_csv) {
  const std::string text = read_all(participants_csv);
  std::vector<std::string> header;
  std::istringstream first(text.substr(0, text.find('\n')));
  for (std::string cell; std::getline(first, cell, ',');) header.push_back(cell);
  const size_t column = size_t(std::find(header.begin(), header.end(), "gaze_source") - header.begin());
  std::map<std::string, std::string> sources;
  for (const auto& row : csv_rows(participants_csv))
    if (column < row.size()) sources[row.front()] = row[column];
  return sources;
}

// A gaze-contingent study (FIPR follows the gaze) whose sessions had gaze from a tracker and from
// the mouse (a rehearsal): the mouse sessions are left out by default, each named with the flag that
// pools them; --gaze-sources takes the kinds asked for, and a study of mouse sessions only is
// analysed and says so. The source is a column of participants.csv and trials.csv.
TEST(AnalyzeCli, MouseSessionsOfAGazeContingentStudyAreKeptApartUnlessAsked) {
  const fs::path folder = scratch("gaze");
  const fs::path config = write_variant(folder, "fipr", "tiny_2afc",
                                        {{"method = \"ipr\"", "method = \"fipr\""}, {"repeats = 4", "repeats = 2"}});
  const fs::path results = folder / "results";
  for (const char* participant : {"P001", "P002", "P003"}) run_session(config.string(), participant, results);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  with_gaze_source(log_of(results, "tiny_2afc", "P001"), "tracker", "pupil:127.0.0.1:50020");
  with_gaze_source(log_of(results, "tiny_2afc", "P002"), "tracker", "pupil:127.0.0.1:50020");
  with_gaze_source(log_of(results, "tiny_2afc", "P003"), "mouse", "mouse");
  const auto before = snapshot(results);
  const fs::path study = results / "tiny_2afc";
  const std::string mouse_log = log_of(results, "tiny_2afc", "P003").string();

  const fs::path out = folder / "out";
  const CommandResult plain = analyze(study.string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_NE(plain.out.find("study tiny_2afc (2afc same): 2 participant(s) (simulated observers), "), std::string::npos)
      << plain.out;
  EXPECT_EQ(participants_of(load_json(out / "thresholds.json")), (std::vector<std::string>{"P001", "P002"}));
  expect_left_out(out, mouse_log, "gaze from the mouse (a rehearsal of a gaze-contingent study)");
  expect_left_out(out, mouse_log, "--gaze-sources all pools them");
  EXPECT_NE(
      read_all(out / "participants.csv").substr(0, read_all(out / "participants.csv").find('\n')).find(",gaze_source,"),
      std::string::npos);
  EXPECT_EQ(gaze_sources_of(out / "participants.csv"),
            (std::map<std::string, std::string>{{"P001", "tracker"}, {"P002", "tracker"}}));
  EXPECT_NE(read_all(out / "report.html").find("gaze source"), std::string::npos);

  const struct {
    const char* filter;
    std::vector<std::string> participants;
    const char* study_line;
  } cases[] = {
      {"all",
       {"P001", "P002", "P003"},
       "3 participant(s) (simulated observers) (mouse gaze pooled with the other sources by --gaze-sources all), "},
      {"mouse", {"P003"}, "1 participant(s) (simulated observers) (mouse gaze: rehearsals), "},
      {"tracker,trace", {"P001", "P002"}, "2 participant(s) (simulated observers), "}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.filter);
    std::string name = std::string("out-") + c.filter;
    std::replace(name.begin(), name.end(), ',', '_');
    const fs::path filtered = folder / name;
    const CommandResult result =
        analyze(study.string() + " --bootstrap 0 --gaze-sources " + c.filter + " --out " + filtered.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find(c.study_line), std::string::npos) << result.out;
    EXPECT_EQ(participants_of(load_json(filtered / "thresholds.json")), c.participants);
  }
  expect_left_out(folder / "out-tracker_trace", mouse_log, "gaze from the mouse (--gaze-sources tracker,trace)");
  EXPECT_EQ(gaze_sources_of(folder / "out-all" / "participants.csv").at("P003"), "mouse");
  // Mouse sessions alone: analysed, and the study line says they are rehearsals.
  const CommandResult alone = analyze(mouse_log + " --bootstrap 0 --out " + (folder / "out-alone").string());
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  EXPECT_NE(alone.out.find("1 participant(s) (simulated observers) (mouse gaze: rehearsals), "), std::string::npos)
      << alone.out;
  // Bad filters: one line, exit 2, nothing written.
  const fs::path bad = folder / "out-bad";
  expect_one_line_error(analyze(study.string() + " --gaze-sources eyes --out " + bad.string()),
                        "--gaze-sources: expected all");
  expect_one_line_error(analyze(study.string() + " --gaze-sources mouse,mouse --out " + bad.string()), "each once");
  expect_one_line_error(analyze(study.string() + " --gaze-sources synthetic --out " + bad.string()),
                        "no session with gaze from a source of the kinds asked for (--gaze-sources synthetic)");
  EXPECT_FALSE(fs::exists(bad));
  // trials.csv names each session's source.
  const fs::path trials = folder / "trials.csv";
  ASSERT_EQ(fovlab_command("export " + study.string() + " --out " + trials.string()).exit_code, 0);
  const std::string csv = read_all(trials);
  EXPECT_NE(csv.find(",track_kind,gaze_source,late_frames\n"), std::string::npos) << csv.substr(0, 400);
  EXPECT_NE(csv.find(",tracker,\n"), std::string::npos);
  EXPECT_NE(csv.find(",mouse,\n"), std::string::npos);
  expect_unchanged(before, results);
}

// Two sessions of one participant ID (each its own header: here another observer): the first log
// in path order is used, the other listed.
TEST(AnalyzeCli, DuplicateParticipantIdUsesTheFirstLog) {
  const fs::path results = scratch("duplicate") / "results";
  run_2afc_participants(results, 2);
  const fs::path elsewhere = scratch("duplicate") / "elsewhere";
  run_session(fixture("tiny_2afc"), "P001", elsewhere, "simulated:guess=0.3,seed=2");
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path copy = results / "tiny_2afc" / "P009";
  fs::copy(elsewhere / "tiny_2afc" / "P001", copy, fs::copy_options::recursive);
  const auto before = snapshot(results);
  const fs::path out = scratch("duplicate") / "out";
  const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_unchanged(before, results);
  const json thresholds = load_json(out / "thresholds.json");
  EXPECT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P002"}));
  EXPECT_EQ(thresholds["participants"][0].value("log_path", ""), log_of(results, "tiny_2afc", "P001").string());
  expect_left_out(out, (copy / "events.jsonl").string(), "duplicate");
  // The other session's trials are not counted: every condition holds the two participants' trials.
  const fs::path out_two = scratch("duplicate") / "out-two";
  fs::remove_all(copy);
  ASSERT_EQ(analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out_two.string()).exit_code, 0);
  EXPECT_EQ(load_json(out_two / "thresholds.json")["conditions"], thresholds["conditions"]);
}

// Issue 37: a participant's folder copied under another name is one session (the same header), not
// two: export wrote its rows twice and analyze called it a duplicate participant. Now both count it
// once and name the copy; a copy taken mid-session (its lines the first of the other's) too.
TEST(AnalyzeCli, ACopiedParticipantFolderIsOneSessionCountedOnce) {
  const fs::path results = scratch("copied") / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path study = results / "tiny_2afc";
  const fs::path original = log_of(results, "tiny_2afc", "P001");
  const fs::path out_once = scratch("copied") / "once";
  const fs::path csv_once = scratch("copied") / "once.csv";
  ASSERT_EQ(analyze(study.string() + " --bootstrap 0 --out " + out_once.string()).exit_code, 0);
  ASSERT_EQ(fovlab_command("export " + study.string() + " --out " + csv_once.string()).exit_code, 0);

  fs::copy(study / "P001", study / "P001b", fs::copy_options::recursive);
  const std::vector<std::string> lines = fovlab::testing::lines_of(read_all(original));
  std::string first_half;
  for (size_t i = 0; i < lines.size() / 2; ++i) first_half += lines[i] + "\n";
  fs::create_directories(study / "P001c");
  std::ofstream(study / "P001c" / "events.jsonl", std::ios::binary) << first_half;
  const auto before = snapshot(results);

  const fs::path out = scratch("copied") / "out";
  const CommandResult analysed = analyze(study.string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  const json thresholds = load_json(out / "thresholds.json");
  EXPECT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P002"}));
  EXPECT_EQ(thresholds["conditions"], load_json(out_once / "thresholds.json")["conditions"]);
  expect_left_out(out, (study / "P001b" / "events.jsonl").string(),
                  "a copy of " + original.string() + " (the same session)");
  expect_left_out(out, (study / "P001c" / "events.jsonl").string(),
                  "a copy of " + original.string() + " (the same session: its " + std::to_string(lines.size() / 2) +
                      " lines are the first of " + std::to_string(lines.size()) + ")");

  const fs::path csv = scratch("copied") / "trials.csv";
  const CommandResult exported = fovlab_command("export " + study.string() + " --out " + csv.string());
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_EQ(read_all(csv), read_all(csv_once));
  EXPECT_NE(exported.err.find((study / "P001b" / "events.jsonl").string() + ": a copy of " + original.string() +
                              " (the same session), left out"),
            std::string::npos)
      << exported.err;
  EXPECT_NE(exported.err.find((study / "P001c" / "events.jsonl").string() + ": a copy of " + original.string()),
            std::string::npos)
      << exported.err;
  expect_unchanged(before, results);
}

// The last response of a 2AFC same/different log's lines answered the other way (the chain not
// rebuilt); returns that line's index.
size_t flip_last_answer(std::vector<std::string>& lines) {
  size_t changed = lines.size();
  while (lines[--changed].find("\"event\":\"response\"") == std::string::npos) {}
  std::string& line = lines[changed];
  const bool same = line.find("\"answer\":\"same\"") != std::string::npos;
  line.replace(line.find("\"answer\":\""), same ? 15 : 20, same ? "\"answer\":\"different\"" : "\"answer\":\"same\"");
  return changed;
}

// Issue 37: two logs of one session that part after a common start (a copy run on, or edited and
// re-chained): neither can be trusted alone, so both are broken at the line where they part, in
// export (refused) and analyze (left out) alike.
TEST(AnalyzeCli, TwoLogsOfOneSessionThatPartAreBothBroken) {
  const fs::path results = scratch("parted") / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path study = results / "tiny_2afc";
  const fs::path original = log_of(results, "tiny_2afc", "P001");
  std::vector<std::string> lines = fovlab::testing::lines_of(read_all(original));
  const size_t changed = flip_last_answer(lines);  // in the copy, its chain rebuilt
  const fs::path copy = study / "P001b" / "events.jsonl";
  fs::create_directories(copy.parent_path());
  std::ofstream(copy, std::ios::binary) << fovlab::testing::rechained(lines);
  const int parting = static_cast<int>(changed) + 1;
  const auto parted = [&](const fs::path& other) {
    return "the same session as " + other.string() + " (the same header), but the two logs part at line " +
           std::to_string(parting) + ": neither can be trusted alone";
  };

  const fs::path out = scratch("parted") / "out";
  const CommandResult analysed = analyze(study.string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  EXPECT_EQ(participants_of(load_json(out / "thresholds.json")), (std::vector<std::string>{"P002"}));
  expect_left_out(out, original.string(), "line " + std::to_string(parting) + ": the log is broken (" + parted(copy));
  expect_left_out(out, copy.string(), "line " + std::to_string(parting) + ": the log is broken (" + parted(original));

  const CommandResult exported =
      fovlab_command("export " + study.string() + " --out " + (scratch("parted") / "t.csv").string());
  expect_one_line_error(
      exported, original.string() + ":" + std::to_string(parting) + ": the log is broken (" + parted(copy) + ")");
}

// Export owns trials.csv and steps.csv beside the one log it reads, and nowhere else: aimed at
// another participant's folder (whose export it would replace, and whose steps.csv --force would
// remove), or at a participant's folder while exporting a whole study, it is refused.
TEST(AnalyzeCli, ExportWritesIntoAParticipantsFolderOnlyBesideTheOneLogItReads) {
  const fs::path results = scratch("export-owned") / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path study = results / "tiny_2afc";
  const fs::path p001 = log_of(results, "tiny_2afc", "P001");
  ASSERT_EQ(fovlab_command("export " + p001.string()).exit_code, 0);  // beside its own log
  ASSERT_TRUE(fs::exists(study / "P001" / "trials.csv"));
  const auto before = snapshot(results);
  const fs::path other = study / "P002" / "trials.csv";
  expect_one_line_error(fovlab_command("export " + p001.string() + " --out " + other.string() + " --force"),
                        "--out " + other.string() + ": inside the participant's folder " + (study / "P002").string() +
                            ", which is not the folder of the one log exported");
  expect_one_line_error(
      fovlab_command("export " + study.string() + " --out " + (study / "P001" / "trials.csv").string() + " --force"),
      "which is not the folder of the one log exported");
  expect_unchanged(before, results);
}

// A backup taken mid-session is intact; the original, longer, was damaged after the backup's last
// line (its chain breaks there). The backup is the session (its lines are all the original's), the
// damaged original left out and named; neither is called parted.
TEST(AnalyzeCli, AnIntactBackupOfALogDamagedLaterIsTheSessionUsed) {
  const fs::path results = scratch("backup") / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path study = results / "tiny_2afc";
  const fs::path original = log_of(results, "tiny_2afc", "P001");
  std::vector<std::string> lines = fovlab::testing::lines_of(read_all(original));
  std::string backup;
  for (size_t i = 0; i < lines.size() / 2; ++i) backup += lines[i] + "\n";
  const fs::path backup_log = study / "P001-backup" / "events.jsonl";
  fs::create_directories(backup_log.parent_path());
  std::ofstream(backup_log, std::ios::binary) << backup;
  // The original's last response edited in place, its chain not rebuilt: broken at that line.
  const size_t changed = flip_last_answer(lines);
  ASSERT_GT(changed, lines.size() / 2);
  std::string damaged;
  for (const std::string& text : lines) damaged += text + "\n";
  std::ofstream(original, std::ios::binary | std::ios::trunc) << damaged;

  const fs::path out = scratch("backup") / "out";
  const CommandResult analysed = analyze(study.string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  EXPECT_EQ(participants_of(load_json(out / "thresholds.json")), (std::vector<std::string>{"P001", "P002"}));
  expect_left_out(out, original.string(),
                  "the same session as " + backup_log.string() + ", longer but its chain broken at line " +
                      std::to_string(changed + 1));
}

// Issue 37: a keyed log read without --lab-key is sealed as far as its chain goes, but its MACs were
// not checked; export and analyze said only "sealed". They still read it, and now say so.
TEST(AnalyzeCli, AKeyedLogReadWithoutTheKeySaysItsMacsWereNotChecked) {
  const fs::path results = scratch("keyed") / "results";
  const fs::path key = fovlab::cli_test::write_file(scratch("keyed") / "lab.key", "0123456789abcdef0123456789abcdef");
  for (const char* participant : {"P001", "P002"}) {
    const CommandResult run =
        fovlab_command("run " + fixture("tiny_2afc") + " --participant " + participant + " --headless --results " +
                       results.string() + " --observer simulated --lab-key " + key.string());
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  const fs::path study = results / "tiny_2afc";
  const std::string note = "MACs not checked (no key given)";

  const fs::path out = scratch("keyed") / "out";
  const CommandResult analysed = analyze(study.string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
  EXPECT_EQ(participants_of(load_json(out / "thresholds.json")), (std::vector<std::string>{"P001", "P002"}));
  EXPECT_NE(analysed.out.find(log_of(results, "tiny_2afc", "P001").string() + ": sealed (keyed; " + note + ")"),
            std::string::npos)
      << analysed.out;
  EXPECT_NE(read_all(out / "report.html").find(note), std::string::npos);
  const CommandResult exported =
      fovlab_command("export " + study.string() + " --out " + (scratch("keyed") / "t.csv").string());
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_NE(exported.err.find(log_of(results, "tiny_2afc", "P002").string() + ": sealed (keyed; " + note + ")"),
            std::string::npos)
      << exported.err;

  // With the key, every MAC is checked and nothing is said.
  const fs::path keyed_out = scratch("keyed") / "keyed-out";
  const CommandResult checked =
      analyze(study.string() + " --bootstrap 0 --lab-key " + key.string() + " --out " + keyed_out.string());
  ASSERT_EQ(checked.exit_code, 0) << checked.err;
  EXPECT_EQ(checked.out.find(note), std::string::npos) << checked.out;
  const CommandResult keyed_export = fovlab_command("export " + study.string() + " --force --lab-key " + key.string() +
                                                    " --out " + (scratch("keyed") / "t.csv").string());
  ASSERT_EQ(keyed_export.exit_code, 0) << keyed_export.err;
  EXPECT_EQ(keyed_export.err.find(note), std::string::npos) << keyed_export.err;
}

// An answer edited in a log breaks its hash chain: the log is left out, the others analysed.
TEST(AnalyzeCli, EditedAnswerBreaksTheChainAndTheLogIsLeftOut) {
  const fs::path results = scratch("edited") / "results";
  run_2afc_participants(results, 3);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path edited = log_of(results, "tiny_2afc", "P002");
  std::string text = read_all(edited);
  const size_t at = text.find("\"answer\":\"same\"");
  const size_t other = text.find("\"answer\":\"different\"");
  ASSERT_TRUE(at != std::string::npos || other != std::string::npos);
  if (at != std::string::npos) text.replace(at, 15, "\"answer\":\"different\"");
  else text.replace(other, 20, "\"answer\":\"same\"");
  std::ofstream(edited, std::ios::binary | std::ios::trunc) << text;

  const auto before = snapshot(results);
  const fs::path out = scratch("edited") / "out";
  const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_unchanged(before, results);
  const json thresholds = load_json(out / "thresholds.json");
  EXPECT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P003"}));
  expect_left_out(out, edited.string(), "chain");
  EXPECT_NE(result.out.find("chain"), std::string::npos) << result.out;
}

// Lines of an events.jsonl that start a trial and are not attention checks.
int comparison_trials(const fs::path& log) {
  std::istringstream text(read_all(log));
  std::string line;
  int count = 0;
  while (std::getline(text, line))
    if (line.find("\"event\":\"trial_start\"") != std::string::npos &&
        line.find("\"attention_check\":false") != std::string::npos)
      ++count;
  return count;
}

// A participant excluded by attention checks is listed but none of their trials is counted.
TEST(AnalyzeCli, ExcludedParticipantIsListedAndNotCounted) {
  const fs::path folder = scratch("excluded");
  const fs::path config = write_variant(folder, "strict_2afc", "tiny_2afc", {{"max_errors = 100", "max_errors = 1"}});
  const fs::path results = folder / "results";
  // An observer who fails attention checks often, with a seed whose first error comes after 25
  // comparison trials (so that "not counted" is not trivially true).
  run_session(config.string(), "P001", results, "simulated:guess=0.3,seed=2");
  run_session(config.string(), "P002", results, "simulated:guess=0,lapse=0");
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path excluded_log = log_of(results, "tiny_2afc", "P001");
  ASSERT_NE(read_all(excluded_log).find("\"event\":\"excluded\""), std::string::npos) << "P001 was not excluded";
  ASSERT_EQ(read_all(log_of(results, "tiny_2afc", "P002")).find("\"event\":\"excluded\""), std::string::npos);
  ASSERT_GT(comparison_trials(excluded_log), 0) << "P001 was excluded before any trial counted";

  const auto before = snapshot(results);
  const fs::path out = folder / "out";
  const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_unchanged(before, results);
  const json thresholds = load_json(out / "thresholds.json");
  ASSERT_EQ(participants_of(thresholds), (std::vector<std::string>{"P001", "P002"}));
  EXPECT_TRUE(thresholds["participants"][0].value("excluded", false));
  EXPECT_FALSE(thresholds["participants"][1].value("excluded", true));
  expect_left_out(out, "participant P001", "excluded");
  // Only P002's comparison trials are counted: per scene, n sums to P002's trials.
  uint64_t counted = 0;
  for (const json& condition : thresholds["conditions"])
    if (condition.value("scene", "") != "all") counted += condition.value("n", 0u);
  EXPECT_EQ(counted, static_cast<uint64_t>(comparison_trials(log_of(results, "tiny_2afc", "P002"))));
  // The guess rate comes from the included participant's checks only (P002 never errs).
  EXPECT_EQ(thresholds.value("guess_rate", -1.0), 0.0) << thresholds.value("guess_rate_source", "");
  const auto rows = csv_rows(out / "participants.csv");
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0][0], "P001");
  EXPECT_EQ(rows[0][2], "true");

  // Only the excluded participant: still a report, saying no one is left.
  const fs::path out_alone = folder / "out-alone";
  const CommandResult alone = analyze(excluded_log.string() + " --bootstrap 0 --out " + out_alone.string());
  EXPECT_EQ(alone.exit_code, 0) << alone.err;
  if (alone.exit_code == 0) {
    expect_left_out(out_alone, "participant P001", "excluded");
    EXPECT_TRUE(load_json(out_alone / "thresholds.json")["conditions"].empty());
  }
}

// Nothing to analyse: exit code 2, one line naming the file or folder, nothing written.
TEST(AnalyzeCli, NothingAnalysableIsOneLineWithExitCode2) {
  const fs::path folder = scratch("nothing");
  const fs::path garbage = folder / "garbage" / "P001" / "events.jsonl";
  fs::create_directories(garbage.parent_path());
  std::ofstream(garbage, std::ios::binary) << "this is not a session log\n";
  const fs::path empty = folder / "empty";
  fs::create_directories(empty);
  const fs::path missing = folder / "no-such-folder";
  const fs::path out = folder / "out";

  const auto before = snapshot(folder);
  expect_one_line_error(analyze((folder / "garbage").string() + " --out " + out.string()), garbage.string());
  expect_one_line_error(analyze(garbage.string() + " --out " + out.string()), garbage.string());
  expect_one_line_error(analyze(empty.string() + " --out " + out.string()), empty.string());
  expect_one_line_error(analyze(missing.string() + " --out " + out.string()), missing.string());
  // An empty log file.
  const fs::path blank = folder / "blank.jsonl";
  std::ofstream(blank, std::ios::binary).flush();
  expect_one_line_error(analyze(blank.string() + " --out " + out.string()), blank.string());
  fs::remove(blank);
  EXPECT_FALSE(fs::exists(out));
  expect_unchanged(before, folder);
}

// Bad flags: exit code 2, one line naming the flag, nothing written under --out.
TEST(AnalyzeCli, BadFlagsAreOneLineAndWriteNothing) {
  const fs::path results = scratch("flags") / "results";
  run_session(fixture("tiny_2afc"), "P001", results);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const auto before = snapshot(results);
  const fs::path out = scratch("flags") / "out";
  const std::string input = (results / "tiny_2afc").string() + " --out " + out.string();
  const std::pair<const char*, const char*> flags[] = {{"--alternative sideways", "--alternative"},
                                                       {"--alpha 0", "--alpha"},
                                                       {"--alpha 1", "--alpha"},
                                                       {"--guess-rate 1.5", "--guess-rate"},
                                                       {"--guess-rate -0.5", "--guess-rate"},
                                                       {"--guess-rate nan", "--guess-rate"},
                                                       {"--rating-cutoff nan", "--rating-cutoff"},
                                                       {"--rating-cutoff 4", "--rating-cutoff"},
                                                       {"--seed -3", "--seed"},
                                                       {"--bootstrap -1", "--bootstrap"},
                                                       {"--bootstrap many", "--bootstrap"}};
  for (const auto& [flag, name] : flags) {
    SCOPED_TRACE(flag);
    const CommandResult result = analyze(input + " " + flag);
    expect_one_line_error(result, name);
    EXPECT_TRUE(result.out.empty()) << result.out;
    EXPECT_FALSE(fs::exists(out)) << flag << " wrote " << out;
    fs::remove_all(out);
  }
  expect_unchanged(before, results);
  // The same folder with good flags is analysed (the failures above were the flags').
  EXPECT_EQ(analyze(input + " --bootstrap 0 --alternative less --alpha 0.01 --guess-rate 0.1").exit_code, 0);
  EXPECT_TRUE(fs::is_regular_file(out / "thresholds.json"));
}

// --alternative greater on a 2afc "which is better" study: the test is named in every output.
TEST(AnalyzeCli, AlternativeGreaterIsNamedInThresholdsAndReport) {
  const fs::path folder = scratch("greater");
  const fs::path config = write_variant(folder, "better_2afc", "tiny_2afc",
                                        {{"question = \"same\"", "question = \"better\""},
                                         // Attention checks need an answer meaning "identical": none.
                                         {"[attention]\nshare = 0.2\nbreak_s = 2\nmax_errors = 100\n", ""}});
  const fs::path results = folder / "results";
  run_session(config.string(), "P001", results);
  run_session(config.string(), "P002", results);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const auto before = snapshot(results);
  const fs::path out = folder / "out";
  const CommandResult result =
      analyze((results / "tiny_2afc").string() + " --alternative greater --bootstrap 20 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  expect_unchanged(before, results);
  const json thresholds = load_json(out / "thresholds.json");
  EXPECT_EQ(thresholds.value("protocol", ""), "2afc");
  EXPECT_EQ(thresholds.value("question", ""), "better");
  EXPECT_EQ(thresholds["test"].value("alternative", ""), "greater");
  EXPECT_EQ(thresholds.value("guess_rate", -1.0), 0.5);
  ASSERT_FALSE(thresholds["conditions"].empty());
  ASSERT_FALSE(thresholds["thresholds"].empty());
  for (const json& threshold : thresholds["thresholds"]) {
    EXPECT_NE(threshold.value("definition", "").find("greater"), std::string::npos) << threshold.dump();
    EXPECT_NE(threshold.value("note", "").find("--alternative greater"), std::string::npos) << threshold.dump();
  }
  const std::string html = read_all(out / "report.html");
  EXPECT_NE(html.find("one-sided (greater)"), std::string::npos);
  EXPECT_EQ(html.find("two-sided"), std::string::npos) << "report.html still names a two-sided test";
  for (const auto& row : csv_rows(out / "conditions.csv")) {
    ASSERT_GE(row.size(), 16u);
    EXPECT_EQ(row[15], "greater");
  }
  EXPECT_NE(result.out.find("greater"), std::string::npos) << result.out;

  // The p-values are the one-sided ones: k >= n/2 gives p <= 1/2, and p is monotone in k.
  const fs::path out_two = folder / "out-two-sided";
  ASSERT_EQ(analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out_two.string()).exit_code, 0);
  const json two_sided = load_json(out_two / "thresholds.json");
  ASSERT_EQ(two_sided["conditions"].size(), thresholds["conditions"].size());
  for (size_t i = 0; i < thresholds["conditions"].size(); ++i) {
    const json& greater = thresholds["conditions"][i];
    const double p_greater = greater.value("p_value", -1.0), p_two = two_sided["conditions"][i].value("p_value", -1.0);
    if (2 * greater.value("k", 0u) > greater.value("n", 0u)) {
      EXPECT_LT(p_greater, p_two) << greater.dump();
    } else {
      EXPECT_GT(p_greater, 0.5) << greater.dump();  // k <= n/2: P(X >= k) > 1/2
    }
  }
}

// --- the output folder as a set (docs/analysis.md, "The output folder") ------------------------------

using fovlab::testing::names_in;
using fovlab::testing::pid_of_a_finished_process;

// A copy of `log` at `to` with header fields replaced, every line's chain recomputed (as if the
// runner had written it so).
void write_log_with_header(const fs::path& log, const fs::path& to, const json& header_fields) {
  const fovlab::EventLogFile file = fovlab::read_event_log(log.string());
  std::string bytes, chain;
  for (size_t i = 0; i < file.events.size(); ++i) {
    json event = file.events[i];
    if (i == 0) event.update(header_fields);
    event.erase("chain");
    if (event.value("event", "") == "seal") event["last_chain"] = chain;  // an unkeyed seal, made again
    chain = fovlab::event_chain(chain, event);
    event["chain"] = chain;
    bytes += event.dump() + "\n";
  }
  fs::create_directories(to.parent_path());
  std::ofstream(to, std::ios::binary) << bytes;
}

// An older build's log of `participant` (a name this build no longer starts): the session of `log`
// made that participant's as a session of it would have been, its session_seed and every trial_start
// as the schedule of the config it carries makes them for that participant, re-chained.
void write_log_of_participant(const fs::path& log, const fs::path& to, const std::string& participant) {
  const fovlab::EventLogFile file = fovlab::read_event_log(log.string());
  const json& header = file.events.front();
  const fovlab::StudyConfig config = fovlab::parse_logged_study_config(
      header["config_toml"].get<std::string>(), log.string(), header["schema_version"].get<int>(), nullptr);
  const fovlab::StudyPlan plan = fovlab::make_study_plan(config, participant);
  std::vector<std::string> lines;
  for (json event : file.events) {
    if (event.value("event", "") == "session_header") {
      event["participant"] = participant;
      event["session_seed"] = plan.session_seed;
    }
    if (event.value("event", "") == "trial_start") {
      const fovlab::Trial& trial = plan.trials.at(event["trial"].get<size_t>());
      event["condition"] = trial.condition;
      event["variant"] = trial.variant;
      if (trial.level) event["level"] = *trial.level;
      else event.erase("level");
      event["attention_check"] = trial.attention_check;
      event["sequence"] = trial.sequence;
      event["reference_first"] = trial.reference_first;
    }
    lines.push_back(event.dump());
  }
  fs::create_directories(to.parent_path());
  std::ofstream(to, std::ios::binary) << fovlab::testing::rechained(lines);
}

// A run leaves exactly the report files at --out, and nothing beside it; the temporaries a killed
// run left beside it (a dead process's) are removed, a running process's are not touched.
TEST(AnalyzeCli, OutputIsCompleteAndKilledRunsLeaveNothingBehind) {
  const fs::path folder = scratch("output-set");
  const fs::path results = folder / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path parent = folder / "reports";
  const fs::path out = parent / "analysis";
  // A run killed while writing (files half there) and one killed after swapping (the old analysis
  // under the temporary name), both of a finished process; and a temporary of a running one.
  const std::string dead = std::to_string(pid_of_a_finished_process());
  const fs::path killed_writing = parent / ("analysis.tmp-" + dead + "-00000000000000aa");
  const fs::path killed_swapping = parent / ("analysis.tmp-" + dead + "-00000000000000bb");
  const fs::path running = parent / ("analysis.tmp-" + std::to_string(::getpid()) + "-00000000000000cc");
  for (const fs::path& path : {killed_writing, killed_swapping, running}) fs::create_directories(path);
  std::ofstream(killed_writing / "thresholds.json") << "{\"study\": \"half";
  std::ofstream(killed_writing / ".conditions.tmp-1.csv") << "study,proto";
  std::ofstream(killed_swapping / "thresholds.json") << "{}";

  const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(names_in(parent), (std::vector<std::string>{"analysis", running.filename().string()}))
      << "a killed run's temporary is still there, or a new one was left";
  const std::vector<std::string> files = names_in(out);
  for (const char* file :
       {"thresholds.json", "conditions.csv", "participants.csv", "report.html", "share_per_level.svg"})
    EXPECT_NE(std::find(files.begin(), files.end(), file), files.end()) << file << " is missing";
  for (const std::string& file : files) {
    EXPECT_NE(file[0], '.') << "hidden temporary left in the output: " << file;
    EXPECT_EQ(file.find(".tmp"), std::string::npos) << file;
  }
  EXPECT_EQ(load_json(out / "thresholds.json").value("study", ""), "tiny_2afc");
  EXPECT_NE(result.out.find("wrote " + std::to_string(files.size()) + " file(s)"), std::string::npos) << result.out;
}

// An earlier analysis is kept unless --force; with it, it is replaced whole. --force never
// replaces a folder holding anything else.
TEST(AnalyzeCli, ExistingOutputNeedsForceAndOnlyAnAnalysisIsReplaced) {
  const fs::path folder = scratch("force");
  const fs::path results = folder / "results";
  run_2afc_participants(results, 2);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const std::string input = (results / "tiny_2afc").string() + " --bootstrap 0";
  const fs::path out = folder / "out";
  ASSERT_EQ(analyze(input + " --out " + out.string()).exit_code, 0);
  const auto first = snapshot(out);

  // Without --force: refused, the earlier analysis byte for byte as it was.
  const CommandResult again = analyze(input + " --alternative less --out " + out.string());
  expect_one_line_error(again, out.string());
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  expect_unchanged(first, out);

  // With --force: the new analysis, whole, and nothing left beside it.
  const CommandResult forced = analyze(input + " --alternative less --force --out " + out.string());
  ASSERT_EQ(forced.exit_code, 0) << forced.err;
  EXPECT_EQ(load_json(out / "thresholds.json")["test"].value("alternative", ""), "less");
  for (const auto& row : csv_rows(out / "conditions.csv")) EXPECT_EQ(row.at(15), "less");
  EXPECT_EQ(names_in(folder), (std::vector<std::string>{"out", "results"}));

  // A folder with anything analyze does not write is not replaced, not even with --force.
  const fs::path mixed = folder / "mixed";
  fs::create_directories(mixed);
  std::ofstream(mixed / "notes.txt") << "keep me";
  const auto logs = snapshot(results);
  for (const fs::path& target : {mixed, results, results / "tiny_2afc"}) {
    SCOPED_TRACE(target.string());
    const auto before = snapshot(target);
    expect_one_line_error(analyze(input + " --force --out " + target.string()), target.string());
    expect_unchanged(before, target);
  }
  expect_unchanged(logs, results);
}

// The study of a log header names the default folder results/<study>/analysis: a name that is a
// path ("../../x", absolute) leaves the log out (exit 2 when it is the only one) and nothing is
// written anywhere.
TEST(AnalyzeCli, StudyNameOfAHeaderCannotMakeAPathOutsideResults) {
  const fs::path folder = scratch("traversal");
  const fs::path made = folder / "made";
  run_session(fixture("tiny_2afc"), "P001", made);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  const fs::path work = folder / "work";
  const fs::path absolute = folder / "absolute";
  for (const std::string& study : {std::string("../../x"), absolute.string(), std::string(".."), std::string("a/b")}) {
    SCOPED_TRACE(study);
    fs::remove_all(work);
    const fs::path log = work / "results" / "evil" / "P001" / "events.jsonl";
    write_log_with_header(log_of(made, "tiny_2afc", "P001"), log, {{"study", study}});
    const auto before = snapshot(folder);
    const CommandResult result = fovlab::cli_test::run_in(work, "analyze results/evil --bootstrap 0");
    expect_one_line_error(result, "results/evil/P001/events.jsonl");
    EXPECT_NE(result.err.find("study"), std::string::npos) << result.err;
    expect_unchanged(before, folder);
    EXPECT_FALSE(fs::exists(folder / "x"));
    EXPECT_FALSE(fs::exists(absolute));
  }
  // Beside a good log of the study, the bad one is left out with its reason.
  fs::remove_all(work);
  write_log_with_header(log_of(made, "tiny_2afc", "P001"), work / "results" / "tiny_2afc" / "P002" / "events.jsonl",
                        {{"study", "../../x"}});
  fs::copy(made / "tiny_2afc" / "P001", work / "results" / "tiny_2afc" / "P001", fs::copy_options::recursive);
  const CommandResult mixed = fovlab::cli_test::run_in(work, "analyze results/tiny_2afc --bootstrap 0");
  ASSERT_EQ(mixed.exit_code, 0) << mixed.err;
  expect_left_out(work / "results" / "tiny_2afc" / "analysis", "results/tiny_2afc/P002/events.jsonl", "study");
  EXPECT_FALSE(fs::exists(folder / "x"));
}

// A participant cannot be called "analysis" (the report folder); a log of one written before that
// rule is never overwritten by the report.
TEST(AnalyzeCli, ParticipantCalledAnalysisCannotShareTheReportFolder) {
  const fs::path folder = scratch("participant-analysis");
  const fs::path results = folder / "results";
  for (const char* id : {"analysis", "Analysis", "ANALYSIS"}) {
    SCOPED_TRACE(id);
    const CommandResult run = fovlab_command("run " + fixture("tiny_2afc") + " --participant " + id +
                                             " --headless --observer simulated --results " + results.string());
    expect_one_line_error(run, std::string("\"") + id + "\" is reserved");
    EXPECT_FALSE(fs::exists(results / "tiny_2afc" / id));
  }
  run_session(fixture("tiny_2afc"), "P001", results);
  ASSERT_FALSE(testing::Test::HasFatalFailure());
  // An older build's log of participant "analysis", in the default report folder.
  const fs::path shared = results / "tiny_2afc" / "analysis";
  write_log_of_participant(log_of(results, "tiny_2afc", "P001"), shared / "events.jsonl", "analysis");
  const auto before = snapshot(results);
  for (const char* force : {"", " --force"}) {
    SCOPED_TRACE(force);
    const CommandResult result = analyze((results / "tiny_2afc").string() + " --bootstrap 0" + force);
    expect_one_line_error(result, shared.string());
    EXPECT_NE(result.err.find("events.jsonl"), std::string::npos) << result.err;
    expect_unchanged(before, results);
  }
  // Another --out: analysed, that participant included.
  const fs::path out = folder / "out";
  ASSERT_EQ(analyze((results / "tiny_2afc").string() + " --bootstrap 0 --out " + out.string()).exit_code, 0);
  EXPECT_EQ(participants_of(load_json(out / "thresholds.json")), (std::vector<std::string>{"P001", "analysis"}));
}

}  // namespace
