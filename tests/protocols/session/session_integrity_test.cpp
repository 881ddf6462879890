// Issue 14: a log says when it was altered. Sessions end sealed; every reader (resume, replay,
// export, the fast scan of analyze) classifies a log as sealed, unsealed or broken; with a lab key a
// forger who rewrites the whole chain is still caught by the seal's MAC; values read from a header
// are checked before they name a folder; hostile lines cannot crash a reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "analysis/study/study_data.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/log_integrity.h"
#include "study/log/session_scan.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "protocols/session/trials_export.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/support/forged_log.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::simulated;
using test::study_fixture;
using testing::forged;
using testing::lines_of;
using testing::rechained;

fs::path write_copy(const fs::path& folder, const std::string& name, const std::string& text) {
  const fs::path path = folder / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

LogIntegrity full_reader(const fs::path& path, const LabKey* key = nullptr) {
  return read_session_record(read_event_log(path.string()), key).integrity;
}

LogIntegrity fast_scan(const fs::path& path, const LabKey* key = nullptr) {
  return scan_session_log(path.string(), key).integrity;
}

ReplayOutcome replay(const fs::path& log_path, const std::string& key_path = "") {
  ReplayOptions options;
  options.log_path = log_path.string();
  options.validation = true;
  options.lab_key_path = key_path;
  return replay_session(options);
}

bool names(const ReplayOutcome& outcome, const std::string& text) {
  for (const std::string& difference : outcome.differences)
    if (difference.find(text) != std::string::npos) return true;
  return false;
}

class SessionIntegrity : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    folder_ = new fs::path(fresh_folder("integrity"));
    key_path_ = new fs::path(*folder_ / "lab.key");
    std::ofstream(*key_path_, std::ios::binary) << "0123456789abcdef0123456789abcdef";
    const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
    SessionOptions options = simulated(*folder_ / "results", "Plain");
    unkeyed_log_ = new std::string(run_session(config, options).log_path);
    options = simulated(*folder_ / "results", "Keyed");
    options.lab_key_path = key_path_->string();
    keyed_log_ = new std::string(run_session(config, options).log_path);
  }
  static LabKey key() { return read_lab_key(key_path_->string()); }
  static fs::path* folder_;
  static fs::path* key_path_;
  static std::string* unkeyed_log_;
  static std::string* keyed_log_;
};
fs::path* SessionIntegrity::folder_ = nullptr;
fs::path* SessionIntegrity::key_path_ = nullptr;
std::string* SessionIntegrity::unkeyed_log_ = nullptr;
std::string* SessionIntegrity::keyed_log_ = nullptr;

TEST_F(SessionIntegrity, AFinishedSessionIsSealedForEveryReader) {
  const LabKey lab_key = key();
  for (const std::string& log : {*unkeyed_log_, *keyed_log_}) {
    SCOPED_TRACE(log);
    const LabKey* given = log == *keyed_log_ ? &lab_key : nullptr;  // a key given for an unkeyed log: broken (below)
    const std::vector<std::string> lines = lines_of(read_file(log));
    EXPECT_EQ(nlohmann::json::parse(lines.back()).value("event", ""), "seal");
    EXPECT_EQ(nlohmann::json::parse(lines.front()).value("schema_version", 0), log_schema_version);
    EXPECT_EQ(nlohmann::json::parse(lines.front())["chain"].get<std::string>().size(), 64u);  // SHA-256
    EXPECT_EQ(full_reader(log, given).status, LogStatus::sealed);
    EXPECT_EQ(fast_scan(log, given).status, LogStatus::sealed);
    const ReplayOutcome replayed = replay(log, given ? key_path_->string() : "");
    EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
    EXPECT_EQ(replayed.integrity.status, LogStatus::sealed);
  }
  EXPECT_TRUE(full_reader(*keyed_log_, &lab_key).mac_checked);
  EXPECT_FALSE(full_reader(*keyed_log_).mac_checked);  // no key given: sealed, MAC unchecked
  EXPECT_FALSE(full_reader(*unkeyed_log_).keyed);
  EXPECT_EQ(full_reader(*unkeyed_log_, &lab_key).status, LogStatus::broken);  // the lab expects its key
  EXPECT_EQ(fast_scan(*unkeyed_log_, &lab_key).status, LogStatus::broken);
}

TEST_F(SessionIntegrity, AnEditedAnswerWithTheChainRecomputedFailsTheKeyedSeal) {
  const LabKey lab_key = key();
  const std::string edited = forged(read_file(*keyed_log_), "\"event\":\"response\"", "\"rt_s\":", "\"rt_s\":1");
  const fs::path path = write_copy(*folder_, "keyed-edited.jsonl", edited);
  EXPECT_EQ(read_event_log(path.string()).first_chain_error_line, 0);  // the forger made the chain whole again
  const LogIntegrity full = full_reader(path, &lab_key);
  EXPECT_EQ(full.status, LogStatus::broken);
  EXPECT_NE(full.reason.find("MAC"), std::string::npos) << full.reason;
  EXPECT_EQ(fast_scan(path, &lab_key).status, LogStatus::broken);
  const ReplayOutcome replayed = replay(path, key_path_->string());
  EXPECT_TRUE(names(replayed, "MAC")) << replayed.difference_count;
  // Without the key, the same log can only be called sealed with its MAC unchecked (documented).
  EXPECT_EQ(full_reader(path).status, LogStatus::sealed);
  EXPECT_FALSE(full_reader(path).mac_checked);
  // A key other than the session's is an error, not a verdict.
  const LabKey other_key =
      read_lab_key(write_copy(*folder_, "other.key", "another key of sixteen bytes or more").string());
  EXPECT_THROW(full_reader(path, &other_key), InputError);
}

TEST_F(SessionIntegrity, AKeyedLogStrippedOfItsKeyOrCutBeforeItsSealCannotBeResealed) {
  const LabKey lab_key = key();
  const std::vector<std::string> lines = lines_of(read_file(*keyed_log_));
  // Every answer flipped, the key id and every MAC removed, the chain made whole again.
  std::vector<std::string> flipped = lines;
  for (std::string& line : flipped)
    if (const size_t at = line.find("\"answer\":\"same\""); at != std::string::npos)
      line.replace(at, 15, "\"answer\":\"different\"");
  const fs::path stripped = write_copy(*folder_, "keyed-stripped.jsonl", rechained(flipped, /*strip_keys=*/true));
  EXPECT_EQ(full_reader(stripped, &lab_key).status, LogStatus::broken);
  EXPECT_EQ(fast_scan(stripped, &lab_key).status, LogStatus::broken);
  EXPECT_EQ(full_reader(stripped, &lab_key).line, 1);
  EXPECT_THROW(export_trials_csv({stripped.string()}, ExportOptions{&lab_key, false}), InputError);

  // The final seal cut off (session_end kept) and the answers rewritten: the next run with the key
  // refuses it instead of sealing it.
  const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  const fs::path results = *folder_ / "reseal";
  const fs::path log = session_log_path(results.string(), config.name, "Keyed");
  fs::create_directories(log.parent_path());
  std::vector<std::string> no_seal(flipped.begin(), flipped.end() - 1);
  std::ofstream(log, std::ios::binary) << rechained(no_seal);
  const std::string before = read_file(log);
  SessionOptions keyed = simulated(results, "Keyed");
  keyed.lab_key_path = key_path_->string();
  EXPECT_THROW(run_session(config, keyed), InputError);
  EXPECT_EQ(read_file(log), before);
  // The same cut without the rewrite (a kill between session_end and its seal): sealed by the next run.
  std::string authentic;
  for (size_t i = 0; i + 1 < lines.size(); ++i) authentic += lines[i] + "\n";
  std::ofstream(log, std::ios::binary | std::ios::trunc) << authentic;
  const SessionOutcome sealed = run_session(config, keyed);
  EXPECT_TRUE(sealed.finished);
  EXPECT_EQ(full_reader(log, &lab_key).status, LogStatus::sealed);
  EXPECT_EQ(lines_of(read_file(log)).size(), lines.size());
}

TEST_F(SessionIntegrity, ADroppedSealOrTrailingCutIsUnsealedAndAWrongCountIsBroken) {
  std::vector<std::string> lines = lines_of(read_file(*unkeyed_log_));
  // Cut at a line boundary (the seal and session_end gone): what a crash leaves, and said so.
  const fs::path cut = write_copy(*folder_, "cut.jsonl", rechained({lines.begin(), lines.end() - 2}));
  EXPECT_EQ(full_reader(cut).status, LogStatus::unsealed);
  EXPECT_EQ(fast_scan(cut).status, LogStatus::unsealed);
  // A seal that commits another trial count than the log holds.
  const std::string wrong =
      forged(read_file(*unkeyed_log_), "\"event\":\"seal\"", "\"trials_complete\":", "\"trials_complete\":9");
  const fs::path wrong_path = write_copy(*folder_, "wrong-count.jsonl", wrong);
  EXPECT_EQ(full_reader(wrong_path).status, LogStatus::broken);
  EXPECT_EQ(fast_scan(wrong_path).status, LogStatus::broken);
  // A plain edit without re-chaining: broken at that line, for both readers.
  std::string edited = read_file(*unkeyed_log_);
  edited.replace(edited.find("\"answer\":\""), 10, "\"answer\":\"x");
  const fs::path edited_path = write_copy(*folder_, "edited.jsonl", edited);
  EXPECT_EQ(full_reader(edited_path).status, LogStatus::broken);
  EXPECT_EQ(fast_scan(edited_path).status, LogStatus::broken);
  EXPECT_EQ(full_reader(edited_path).line, fast_scan(edited_path).line);
}

TEST_F(SessionIntegrity, ADuplicatedTrialIsRefusedByBothReaders) {
  std::vector<std::string> lines = lines_of(read_file(*unkeyed_log_));
  size_t start = 0, end = 0;
  for (size_t i = 0; i < lines.size() && !end; ++i) {
    if (!start && lines[i].find("\"event\":\"trial_start\"") != std::string::npos) start = i;
    if (start && lines[i].find("\"event\":\"trial_end\"") != std::string::npos) end = i;
  }
  ASSERT_GT(end, start);
  std::vector<std::string> doubled(lines.begin(), lines.begin() + static_cast<long>(end) + 1);
  doubled.insert(doubled.end(), lines.begin() + static_cast<long>(start), lines.begin() + static_cast<long>(end) + 1);
  doubled.insert(doubled.end(), lines.begin() + static_cast<long>(end) + 1, lines.end());
  const fs::path path = write_copy(*folder_, "duplicated.jsonl", rechained(doubled));
  EXPECT_THROW(read_session_record(read_event_log(path.string())), InputError);
  EXPECT_THROW(scan_session_log(path.string()), InputError);
}

TEST_F(SessionIntegrity, BothReadersHoldTheSameFieldTypesAndSeqRule) {
  const std::string original = read_file(*unkeyed_log_);
  // Fields the full reader does not use in that event, but the scan decodes in every event.
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"\"event\":\"session_end\"", "\"event\":\"session_end\",\"trial\":3.0"},
           {"\"event\":\"session_end\"", "\"event\":\"session_end\",\"condition\":5"},
           {"\"event\":\"trial_end\",", "\"event\":\"trial_end\",\"block\":4294967296,"}}) {
    SCOPED_TRACE(to);
    const fs::path path = write_copy(*folder_, "types.jsonl", forged(original, from, from, to));
    EXPECT_THROW(read_session_record(read_event_log(path.string())), InputError);
    EXPECT_THROW(scan_session_log(path.string()), InputError);
  }
  // A seq that is not an integer: the chain breaks there, for both.
  std::vector<std::string> lines = lines_of(original);
  const size_t at = lines[3].find("\"seq\":3");
  ASSERT_NE(at, std::string::npos);
  lines[3].replace(at, 7, "\"seq\":3.5");
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  const fs::path path = write_copy(*folder_, "seq.jsonl", text);
  EXPECT_EQ(full_reader(path).status, LogStatus::broken);
  EXPECT_EQ(fast_scan(path).status, LogStatus::broken);
  EXPECT_EQ(full_reader(path).line, 4);
  EXPECT_EQ(fast_scan(path).line, 4);
}

TEST_F(SessionIntegrity, ReplayChecksTheHeaderAgainstItsOwnConfig) {
  const std::string original = read_file(*unkeyed_log_);
  const std::string hash_edited = forged(original, "session_header", "\"config_hash\":\"", "\"config_hash\":\"00");
  const ReplayOutcome hash = replay(write_copy(*folder_, "config-hash.jsonl", hash_edited));
  EXPECT_TRUE(names(hash, "config_hash")) << hash.difference_count;
  const std::string study_edited =
      forged(original, "session_header", "\"study\":\"tiny_2afc\"", "\"study\":\"other_study\"");
  const ReplayOutcome study = replay(write_copy(*folder_, "study.jsonl", study_edited));
  EXPECT_TRUE(names(study, "study")) << study.difference_count;
}

TEST_F(SessionIntegrity, AHeaderStudyOrParticipantThatIsNotAFolderNameIsRefused) {
  const std::string original = read_file(*unkeyed_log_);
  for (const std::string bad : {"../../x", "/tmp/x", "..", ".hidden", "a/b"}) {
    SCOPED_TRACE(bad);
    const std::string study =
        forged(original, "session_header", "\"study\":\"tiny_2afc\"", "\"study\":\"" + bad + "\"");
    const fs::path path = write_copy(*folder_, "bad-study.jsonl", study);
    EXPECT_THROW(read_session_record(read_event_log(path.string())), InputError);
    EXPECT_THROW(scan_session_log(path.string()), InputError);
    const std::string participant =
        forged(original, "session_header", "\"participant\":\"Plain\"", "\"participant\":\"" + bad + "\"");
    const fs::path participant_path = write_copy(*folder_, "bad-participant.jsonl", participant);
    EXPECT_THROW(scan_session_log(participant_path.string()), InputError);
  }
}

TEST_F(SessionIntegrity, ExportRefusesABrokenLogUnlessAskedAndSaysEachRowsStatus) {
  std::string edited = read_file(*unkeyed_log_);
  edited.replace(edited.find("\"answer\":\"same\""), 15, "\"answer\":\"different\"");
  const fs::path broken = write_copy(*folder_, "export-broken.jsonl", edited);
  EXPECT_THROW(export_trials_csv({broken.string()}), InputError);
  ExportOptions include;
  include.include_broken = true;
  const std::string csv = export_trials_csv({broken.string()}, include);
  EXPECT_NE(csv.find(",broken,"), std::string::npos);
  EXPECT_NE(export_trials_csv({*unkeyed_log_}).find(",sealed,"), std::string::npos);
  EXPECT_NE(csv.substr(0, csv.find('\n')).find("log_status"), std::string::npos);
}

TEST_F(SessionIntegrity, AForgedLogIsNotResumed) {
  const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  std::vector<std::string> lines = lines_of(read_file(*unkeyed_log_));
  // The first half of the session, its trial indices moved past the end of the plan.
  std::vector<std::string> half(lines.begin(), lines.begin() + static_cast<long>(lines.size() / 2));
  std::string text = rechained(half);
  for (size_t at = text.find("\"trial\":"); at != std::string::npos; at = text.find("\"trial\":", at + 1))
    text.replace(at, 8, "\"trial\":9");
  const fs::path results = *folder_ / "forged-results";
  const fs::path log = session_log_path(results.string(), config.name, "Plain");
  fs::create_directories(log.parent_path());
  std::ofstream(log, std::ios::binary) << rechained(lines_of(text));
  const std::string before = read_file(log);
  try {
    run_session(config, simulated(results, "Plain"));
    ADD_FAILURE() << "a forged log was resumed";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("not in this study's plan"), std::string::npos) << error.what();
  }
  EXPECT_EQ(read_file(log), before);
}

TEST_F(SessionIntegrity, HostileLinesAreRefusedWithoutCrashingEitherReader) {
  // An object line whose member nests 100,000 deep: the fast scan's fallback parser used to recurse
  // on it and overflow the stack.
  std::vector<std::string> lines = lines_of(read_file(*unkeyed_log_));
  std::string deep = lines[1];
  deep.insert(deep.size() - 1, ",\"x\":" + std::string(100000, '[') + std::string(100000, ']'));
  lines[1] = deep;
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  const fs::path path = write_copy(*folder_, "deep.jsonl", text);
  EXPECT_THROW(read_event_log(path.string()), InputError);
  try {
    EXPECT_EQ(scan_session_log(path.string()).integrity.status, LogStatus::broken);
  } catch (const InputError&) {  // refused outright: as good
  }
  // The same depth in the header line.
  lines = lines_of(read_file(*unkeyed_log_));
  lines[0].insert(lines[0].size() - 1, ",\"x\":" + std::string(100000, '[') + std::string(100000, ']'));
  text.clear();
  for (const std::string& line : lines) text += line + "\n";
  const fs::path header_path = write_copy(*folder_, "deep-header.jsonl", text);
  EXPECT_THROW(scan_session_log(header_path.string()), InputError);
}

// Issue 37: a field nested one level past the cap in one event, the chain rebuilt over it. The fast
// scan of analyze used to count the trial (its fast chain path never looked at the depth) while
// export, replay and resume refused it: one line reader now, so every reader refuses it, in the
// same words; one level less is read by every reader.
TEST_F(SessionIntegrity, ALineNestedPastTheCapIsRefusedByEveryReaderAlike) {
  const std::string original = read_file(*unkeyed_log_);
  const auto with_field = [&](int depth) {  // a response with "x" nested `depth` levels (the line's object is 1)
    return forged(
        original, "\"event\":\"response\"", "\"event\":\"response\"",
        "\"event\":\"response\",\"x\":" + std::string(size_t(depth - 1), '[') + std::string(size_t(depth - 1), ']'));
  };
  const std::string deep = with_field(max_event_nesting + 1);
  const std::vector<std::string> lines = lines_of(deep);
  int line = 0;
  while (lines[size_t(line)].find("\"x\":") == std::string::npos) ++line;
  ++line;

  const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  const fs::path results = *folder_ / "deep-results";
  const fs::path log = session_log_path(results.string(), config.name, "Plain");
  fs::create_directories(log.parent_path());
  std::ofstream(log, std::ios::binary) << deep;
  const std::string reason = "not a session event (nested deeper than 32 levels)";
  const std::string refused = log.string() + ":" + std::to_string(line) + ": " + reason;
  const auto expect_refused = [&](const char* reader, const auto& read, const std::string& words) {
    SCOPED_TRACE(reader);
    try {
      read();
      ADD_FAILURE() << reader << " read a line nested deeper than the cap";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
    }
  };
  expect_refused(
      "full reader", [&] { read_event_log(log.string()); }, refused);
  expect_refused(
      "fast scan", [&] { scan_session_log(log.string()); }, refused);
  expect_refused(
      "export", [&] { export_trials_csv({log.string()}); }, refused);
  // Its only log left out, analyze has nothing to analyse and says why.
  expect_refused(
      "analyze", [&] { analysis::load_study({log.string()}); },
      log.string() + ": line " + std::to_string(line) + ": " + reason);
  expect_refused(
      "replay", [&] { replay(log); }, refused);
  expect_refused(
      "resume", [&] { run_session(config, simulated(results, "Plain")); }, refused);
  EXPECT_EQ(read_file(log), deep);

  const fs::path at_cap = write_copy(*folder_, "at-cap.jsonl", with_field(max_event_nesting));
  EXPECT_EQ(full_reader(at_cap).status, LogStatus::sealed);
  EXPECT_EQ(fast_scan(at_cap).status, LogStatus::sealed);
  EXPECT_EQ(scan_session_log(at_cap.string()).trials.size(),
            read_session_record(read_event_log(at_cap.string())).trials.size());
}

// Issue 37: what replay alone checked, export and analyze check too. A trial deleted (in the middle,
// or the last of a session that says it completed), a trial added, or the header's config_hash
// edited, and the chain and seals rebuilt by a forger without the key: the chain holds, so only
// the checks against the log's own header catch it. Both report it broken at the same line for
// the same reason; export refuses it unless --include-broken, analyze leaves it out.
TEST_F(SessionIntegrity, ExportAndAnalyzeCatchATrialDeletedOrAddedOrAnEditedConfigHash) {
  const std::vector<std::string> lines = lines_of(read_file(*unkeyed_log_));
  // The lines of each trial, from its trial_start to its trial_end.
  std::vector<std::pair<size_t, size_t>> trials;
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].find("\"event\":\"trial_start\"") != std::string::npos) trials.emplace_back(i, i);
    if (lines[i].find("\"event\":\"trial_end\"") != std::string::npos) trials.back().second = i;
  }
  ASSERT_GT(trials.size(), 4u);
  const auto without = [&](size_t trial) {
    std::vector<std::string> kept = lines;
    kept.erase(kept.begin() + long(trials[trial].first), kept.begin() + long(trials[trial].second) + 1);
    return kept;
  };
  const auto line_of = [](const std::vector<std::string>& text, const std::string& needle) {
    for (size_t i = 0; i < text.size(); ++i)
      if (text[i].find(needle) != std::string::npos) return int(i) + 1;
    return 0;
  };
  const int count = int(trials.size());
  // A trial added after the last: trial 1's events under a new index.
  std::vector<std::string> added = lines;
  size_t end = 0;
  while (added[end].find("\"event\":\"session_end\"") == std::string::npos) ++end;
  for (size_t i = trials[1].first; i <= trials[1].second; ++i) {
    std::string copy = lines[i];
    const size_t at = copy.find("\"trial\":1");
    ASSERT_NE(at, std::string::npos) << copy;
    copy.replace(at, 9, "\"trial\":" + std::to_string(count));
    added.insert(added.begin() + long(end++), copy);
  }
  const std::vector<std::string> middle = without(2), last = without(size_t(count - 1));
  const std::vector<std::string> hashed =
      lines_of(forged(read_file(*unkeyed_log_), "session_header", "\"config_hash\":\"", "\"config_hash\":\"00"));
  const std::string hash = nlohmann::json::parse(lines.front())["config_hash"].get<std::string>();
  struct Case {
    const char* name;
    std::vector<std::string> lines;
    int line;
    std::string reason;
  };
  const std::vector<Case> cases = {
      {"middle trial deleted", middle, line_of(middle, "\"trial\":3,"),
       "trial 2: missing from the log before trial 3 (the schedule runs it)"},
      {"last trial deleted", last, line_of(last, "\"event\":\"session_end\""),
       "session_end: the session says it completed, but the log holds " + std::to_string(count - 1) + " of " +
           std::to_string(count) + " trials and the schedule runs more"},
      {"trial added", added, line_of(added, "\"trial\":" + std::to_string(count)),
       "trial " + std::to_string(count) + ": not in this study's plan (" + std::to_string(count) + " trials)"},
      {"config_hash edited", hashed, 1,
       "header: config_hash 00" + hash + " is not the hash of its config_toml (" + hash + ")"}};
  for (const Case& forgery : cases) {
    SCOPED_TRACE(forgery.name);
    const fs::path folder = *folder_ / "forged" / forgery.name;
    fs::create_directories(folder);
    const fs::path path = write_copy(folder, "events.jsonl", rechained(forgery.lines, false, /*recount_seals=*/true));
    EXPECT_EQ(full_reader(path).status, LogStatus::sealed);  // the chain and the seals hold
    EXPECT_EQ(fast_scan(path).status, LogStatus::sealed);
    const std::string broken = "the log is broken (" + forgery.reason + ")";
    try {
      export_trials_csv({path.string()});
      ADD_FAILURE() << "exported";
    } catch (const InputError& error) {
      EXPECT_NE(std::string(error.what()).find(path.string() + ":" + std::to_string(forgery.line) + ": " + broken),
                std::string::npos)
          << error.what();
    }
    ExportOptions include;
    include.include_broken = true;
    EXPECT_NE(export_trials_csv({path.string()}, include).find(",broken,"), std::string::npos);
    // Analysed beside another session's log: this one left out, with the same words.
    const analysis::StudyData data = analysis::load_study({path.string(), *keyed_log_});
    ASSERT_EQ(data.participants.size(), 1u);
    EXPECT_EQ(data.participants.front().participant, "Keyed");
    bool named = false;
    for (const analysis::LeftOut& item : data.left_out)
      named = named || (item.what == path.string() &&
                        item.reason.find("line " + std::to_string(forgery.line) + ": " + broken) != std::string::npos);
    EXPECT_TRUE(named) << (data.left_out.empty() ? std::string("nothing left out") : data.left_out.front().reason);
    analysis::LoadOptions all;
    all.include_broken = true;
    const analysis::StudyData with_broken = analysis::load_study({path.string(), *keyed_log_}, all);
    EXPECT_TRUE(
        std::any_of(with_broken.participants.begin(), with_broken.participants.end(), [&](const auto& participant) {
          return participant.log_path == path.string() && participant.log_status == LogStatus::broken;
        }));
  }
}

// Issue 37: replay read the config a log carries under the name of the config file the session ran
// with, so a fault in the log's config_toml was reported against that file, which holds none.
TEST_F(SessionIntegrity, AFaultInALogsConfigTextNamesTheLog) {
  const std::string edited =
      forged(read_file(*unkeyed_log_), "session_header", "repeats = 4", "repeats = \\\"four\\\"");
  const fs::path path = write_copy(*folder_, "bad-config-toml.jsonl", edited);
  try {
    replay(path);
    ADD_FAILURE() << "replayed a log whose config_toml cannot be read";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()).rfind(path.string() + ":1: config_toml", 0), 0u) << error.what();
    EXPECT_NE(std::string(error.what()).find("repeats"), std::string::npos) << error.what();
  }
  // Export and analyze: broken at the header, naming the log.
  try {
    export_trials_csv({path.string()});
    ADD_FAILURE() << "exported a log whose config_toml cannot be read";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what())
                  .find(path.string() + ":1: the log is broken (header: its config_toml cannot be read (" +
                        path.string() + " (config_toml)"),
              std::string::npos)
        << error.what();
  }
}

TEST_F(SessionIntegrity, AnOversizedLogOrAFolderIsRefusedBeforeAnythingIsRead) {
  const fs::path huge = *folder_ / "huge.jsonl";
  std::ofstream(huge, std::ios::binary) << read_file(*unkeyed_log_);
  fs::resize_file(huge, max_log_bytes + 1);  // sparse: no disk, and never read
  for (const fs::path& path : {huge, *folder_}) {
    SCOPED_TRACE(path.string());
    EXPECT_THROW(read_event_log(path.string()), InputError);
    EXPECT_THROW(scan_session_log(path.string()), InputError);
  }
  try {
    read_event_log(huge.string());
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("1024 MiB"), std::string::npos) << error.what();
  }
}

TEST_F(SessionIntegrity, AByteOrderMarkIsReadTheSameByEveryReader) {
  const fs::path path = write_copy(*folder_, "bom.jsonl", "\xEF\xBB\xBF" + read_file(*unkeyed_log_));
  EXPECT_EQ(full_reader(path).status, LogStatus::sealed);
  EXPECT_EQ(fast_scan(path).status, LogStatus::sealed);
  EXPECT_EQ(scan_session_log(path.string()).trials.size(),
            read_session_record(read_event_log(path.string())).trials.size());
}

TEST_F(SessionIntegrity, ALabKeyInsideTheResultsFolderOrTooShortIsRefused) {
  const fs::path results = *folder_ / "key-results";
  fs::create_directories(results);
  const fs::path inside = write_copy(results, "lab.key", "0123456789abcdef0123");
  EXPECT_THROW(read_lab_key(inside.string(), results.string()), InputError);
  EXPECT_NO_THROW(read_lab_key(key_path_->string(), results.string()));
  const fs::path short_key = write_copy(*folder_, "short.key", "short");
  EXPECT_THROW(read_lab_key(short_key.string()), InputError);
  EXPECT_THROW(read_lab_key(folder_->string()), InputError);
  // Resuming a keyed session without its key, or an unkeyed one with a key, is refused.
  const StudyConfig config = parse_study_config_file(study_fixture("tiny_2afc").string(), renderer_scene_catalog());
  std::vector<std::string> lines = lines_of(read_file(*keyed_log_));
  const fs::path resume_results = *folder_ / "resume-keyed";
  const fs::path log = session_log_path(resume_results.string(), config.name, "Keyed");
  fs::create_directories(log.parent_path());
  std::string half;
  for (size_t i = 0; i < lines.size() / 2; ++i) half += lines[i] + "\n";
  std::ofstream(log, std::ios::binary) << half;
  EXPECT_THROW(run_session(config, simulated(resume_results, "Keyed")), InputError);
  SessionOptions keyed = simulated(resume_results, "Keyed");
  keyed.lab_key_path = key_path_->string();
  const SessionOutcome resumed = run_session(config, keyed);
  EXPECT_TRUE(resumed.resumed && resumed.finished);
  const LabKey lab_key = key();
  EXPECT_EQ(full_reader(resumed.log_path, &lab_key).status, LogStatus::sealed);
  EXPECT_TRUE(full_reader(resumed.log_path, &lab_key).mac_checked);
}

}  // namespace
}  // namespace fovlab
