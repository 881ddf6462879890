// Issue 14: two `fovlab run` of one participant. Each race is lined up exactly with the test-only
// pause points (core/test_pause.h): the first process stops itself at a phase (SIGSTOP), the
// second runs in full, then the first continues. The participant's lock, taken before anything is
// read, makes the second change nothing and exit 2 naming the first; the first then finishes a
// whole, single session.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <map>
#include <thread>

#include "app/commands.h"
#include "app/output_options.h"
#include "core/session_files.h"

#include "protocols/stimuli/stimulus_settings.h"
#include "core/input_error.h"
#include "study/log/log_integrity.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "tests/app/cli_test_support.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/support/fovlab_child.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

struct Child {
  pid_t pid = -1;
  fs::path output;  // stdout and stderr
};

// `fovlab run` of the pair fixture for participant R1; `pause_at`: a pause point (core/test_pause.h),
// or "".
Child start_run(const fs::path& results, const std::string& pause_at, const std::string& name) {
  Child child;
  child.output = results.parent_path() / (name + "-output.txt");
  child.pid = test::start_fovlab({"run", test::study_fixture("pair").string(), "--participant", "R1", "--observer",
                                  "simulated", "--headless", "--results", results.string()},
                                 pause_at, child.output);
  return child;
}

using test::exit_code;
using test::wait_until_stopped;

int count_of(const std::string& text, const std::string& needle) {
  int count = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++count;
  return count;
}

void expect_one_whole_session(const std::string& log_path) {
  const std::string text = test::read_file(log_path);
  EXPECT_EQ(count_of(text, "\"event\":\"session_header\""), 1);
  const SessionRecord record = read_session_record(read_event_log(log_path));
  EXPECT_TRUE(record.ended);
  EXPECT_EQ(record.integrity.status, LogStatus::sealed) << record.integrity.describe();
  ReplayOptions replay;
  replay.log_path = log_path;
  replay.validation = true;
  EXPECT_EQ(replay_session(replay).difference_count, 0);
}

// Before: run A checked that no log existed, then spent seconds preparing stimuli; run B, started
// in that window, also saw no log, so both wrote a session into one file (two headers, seq from 0).
TEST(SessionRace, ASecondRunDuringTheFirstsPreparationChangesNothing) {
  const fs::path root = test::fresh_folder("race-new");
  const fs::path results = root / "results";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
  const Child first = start_run(results, "prepared", "first");
  ASSERT_TRUE(wait_until_stopped(first.pid)) << test::read_file(first.output);
  const Child second = start_run(results, "", "second");
  EXPECT_EQ(exit_code(second.pid), 2) << test::read_file(second.output);
  const std::string refused = test::read_file(second.output);
  EXPECT_NE(refused.find("another fovlab process runs this participant (pid " + std::to_string(first.pid)),
            std::string::npos)
      << refused;
  EXPECT_FALSE(fs::exists(log_path));  // the first has not written yet, and the second wrote nothing
  kill(first.pid, SIGCONT);
  EXPECT_EQ(exit_code(first.pid), 0) << test::read_file(first.output);
  expect_one_whole_session(log_path);
}

// Before: run B set a torn last line aside and truncated the log from what it had read, before it
// took the lock, while run A was appending: A's events were cut. Now the lock comes first.
TEST(SessionRace, ASecondRunCannotCutALogWithATornTailThatTheFirstResumes) {
  const fs::path root = test::fresh_folder("race-torn");
  // A whole session, then its first part with half a line after it (what a crash leaves).
  const fs::path whole_results = root / "whole";
  const Child whole = start_run(whole_results, "", "whole");
  ASSERT_EQ(exit_code(whole.pid), 0) << test::read_file(whole.output);
  const std::string whole_log = session_log_path(whole_results.string(), "tiny_pair", "R1");
  const std::string text = test::read_file(whole_log);
  const size_t cut = text.find('\n', text.size() / 3) + 1 + 25;

  const fs::path results = root / "results";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
  fs::create_directories(fs::path(log_path).parent_path());
  std::ofstream(log_path, std::ios::binary) << text.substr(0, cut);
  const Child first = start_run(results, "locked", "first");
  ASSERT_TRUE(wait_until_stopped(first.pid)) << test::read_file(first.output);
  const Child second = start_run(results, "", "second");
  EXPECT_EQ(exit_code(second.pid), 2) << test::read_file(second.output);
  EXPECT_EQ(test::read_file(log_path), text.substr(0, cut));  // untouched: torn tail still there
  EXPECT_FALSE(fs::exists(log_path + ".torn-1"));
  kill(first.pid, SIGCONT);
  EXPECT_EQ(exit_code(first.pid), 0) << test::read_file(first.output);
  EXPECT_TRUE(fs::exists(log_path + ".torn-1"));
  EXPECT_EQ(test::trial_summary(log_path), test::trial_summary(whole_log));
  const SessionRecord record = read_session_record(read_event_log(log_path));
  EXPECT_EQ(record.integrity.status, LogStatus::sealed);
}

TEST(SessionRace, AParticipantFolderThatIsASymbolicLinkIsRefused) {
  const fs::path root = test::fresh_folder("race-symlink");
  const fs::path outside = root / "outside";
  fs::create_directories(outside);
  fs::create_directories(root / "results" / "tiny_pair");
  fs::create_directory_symlink(outside, root / "results" / "tiny_pair" / "R1");
  const Child run = start_run(root / "results", "", "symlink");
  EXPECT_EQ(exit_code(run.pid), 2) << test::read_file(run.output);
  EXPECT_NE(test::read_file(run.output).find("symbolic link"), std::string::npos) << test::read_file(run.output);
  EXPECT_TRUE(fs::is_empty(outside));
}

TEST(SessionRace, AStartThatFailsAfterTakingTheLockLeavesNoFolder) {
  const fs::path results = test::fresh_folder("race-failed-start");
  const StudyConfig config = parse_study_config_file(test::study_fixture("pair").string(), renderer_scene_catalog());
  SessionOptions options = test::simulated(results, "F1");
  options.gaze = "trace:" + (results / "no-such-trace.csv").string();  // read after the lock is taken
  EXPECT_THROW(run_session(config, options), InputError);
  EXPECT_TRUE(fs::is_empty(results)) << "a failed start left " << fs::directory_iterator(results)->path();
}

// Issue 37: every output option of every command, aimed at a live session's files, is refused at
// once (exit 2, one line) and changes nothing; the session, stopped after its second trial while
// all of it ran, then ends as an uninterrupted one does.

// Every command line option registered by app/output_options.h: the command's words ("slurm
// prerender"), the option and its kind, read from the command-line definition itself.
struct OutputOptionUse {
  std::string command;
  std::string flag;
  OutputKind kind;
};

void visit_commands(CLI::App& command, const std::string& words,
                    const std::function<void(CLI::App&, const std::string&)>& each) {
  each(command, words);
  for (CLI::App* sub : command.get_subcommands([](CLI::App*) { return true; }))
    visit_commands(*sub, words.empty() ? sub->get_name() : words + " " + sub->get_name(), each);
}

std::vector<OutputOptionUse> every_output_option(CLI::App& app) {
  std::vector<OutputOptionUse> uses;
  visit_commands(app, "", [&](CLI::App& command, const std::string& words) {
    for (CLI::Option* option : command.get_options())
      if (const std::optional<OutputKind> kind = app::output_kind_of(*option))
        uses.push_back({words, option->get_name(), *kind});
  });
  return uses;
}

// A new option that writes must be registered as an output: any option taking a value whose name
// says output (out, json, svg, csv, dir, cache, screenshots, results) or whose help says it writes.
TEST(SessionRace, EveryOptionThatLooksLikeAnOutputIsRegisteredAsOne) {
  CLI::App app;
  app::add_commands(app);
  const std::set<std::string> output_words = {"out", "json", "svg", "csv", "dir", "cache", "screenshots", "results"};
  int outputs = 0;
  visit_commands(
      app, "", [&](CLI::App& command, const std::string& words) {
        for (CLI::Option* option : command.get_options()) {
          if (option->get_positional() || option->get_expected_min() == 0) continue;  // inputs, and flags
          std::string help = option->get_description();
          std::transform(help.begin(), help.end(), help.begin(), [](unsigned char c) { return char(std::tolower(c)); });
          bool looks = help.find("write") != std::string::npos;
          std::stringstream name(option->get_name());
          for (std::string word; std::getline(name, word, '-');) looks = looks || output_words.count(word) > 0;
          const bool registered = app::output_kind_of(*option).has_value();
          outputs += registered;
          EXPECT_TRUE(registered || !looks)
              << "fovlab " << words << " " << option->get_name()
              << " looks like an output: register it with add_output_option (app/output_options.h)";
        }
      });
  EXPECT_GE(outputs, 30);  // the command line has at least these today
}

TEST(SessionRace, EveryOutputOptionAimedAtALiveSessionIsRefusedAndTheSessionEndsAsIfNothingHappened) {
  const fs::path root = test::fresh_folder("race-outputs");
  const Child whole = start_run(root / "whole", "", "whole");  // the uninterrupted session
  ASSERT_EQ(exit_code(whole.pid), 0) << test::read_file(whole.output);

  const fs::path results = root / "results";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
  const fs::path folder = fs::path(log_path).parent_path();
  const Child live = start_run(results, "trial_end:2", "live");
  ASSERT_TRUE(wait_until_stopped(live.pid)) << test::read_file(live.output);
  std::map<std::string, std::string> before;
  for (const auto& entry : fs::directory_iterator(folder))
    before[entry.path().filename()] = test::read_file(entry.path());
  ASSERT_TRUE(before.count("events.jsonl"));

  // The same files by other names: a link to the log, a link to the folder.
  const fs::path outside = root / "outside";
  fs::create_directories(outside);
  fs::create_symlink(log_path, outside / "link.json");
  fs::create_directory_symlink(folder, outside / "participant");

  CLI::App app;
  app::add_commands(app);
  const std::vector<OutputOptionUse> uses = every_output_option(app);
  for (const OutputOptionUse& use : uses) {
    std::vector<fs::path> targets;
    if (use.kind == OutputKind::folder) {
      targets = {folder, folder / "sub", outside / "participant"};
    } else {
      const std::string name = use.kind == OutputKind::image_file ? "x.png" : "x.json";
      targets = {log_path, outside / "link.json", folder / std::string(kSessionLockName), folder / name,
                 outside / "participant" / name};
    }
    for (const fs::path& target : targets) {
      const cli_test::CommandResult result = cli_test::run(use.command + " " + use.flag + " " + target.string());
      SCOPED_TRACE("fovlab " + use.command + " " + use.flag + " " + target.string());
      cli_test::expect_one_line_error(result, use.flag + ": ");
    }
  }
  std::map<std::string, std::string> after;
  for (const auto& entry : fs::directory_iterator(folder))
    after[entry.path().filename()] = test::read_file(entry.path());
  EXPECT_TRUE(before == after) << "a command changed the live session's folder";

  kill(live.pid, SIGCONT);
  EXPECT_EQ(exit_code(live.pid), 0) << test::read_file(live.output);
  expect_one_whole_session(log_path);
  EXPECT_EQ(test::trial_summary(log_path),
            test::trial_summary(session_log_path((root / "whole").string(), "tiny_pair", "R1")));
}

// Issue 37: another program gives the log's name to another file (a rename onto it, as an atomic
// write or an editor's save does) or removes it while the session runs. The session notices at its
// next event, copies every event from the file it holds open to events.jsonl.recovered-1, says so
// and stops (exit 2); the next run puts that copy back, keeps the other file as
// events.jsonl.replaced-1, and ends as an uninterrupted session.
TEST(SessionRace, ALogReplacedOrRemovedUnderARunningSessionIsKeptAndTheNextRunResumesFromIt) {
  const fs::path root = test::fresh_folder("race-replaced");
  const Child whole = start_run(root / "whole", "", "whole");
  ASSERT_EQ(exit_code(whole.pid), 0) << test::read_file(whole.output);
  const auto whole_trials = test::trial_summary(session_log_path((root / "whole").string(), "tiny_pair", "R1"));

  for (const bool removed : {false, true}) {
    SCOPED_TRACE(removed ? "the log removed" : "the log replaced");
    const fs::path results = root / (removed ? "removed" : "replaced");
    const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
    const Child live = start_run(results, "trial_end:2", removed ? "removed" : "replaced");
    ASSERT_TRUE(wait_until_stopped(live.pid)) << test::read_file(live.output);
    const std::string written = test::read_file(log_path);
    const std::string foreign = "{\"written_by\":\"another program\"}\n";
    if (removed) {
      fs::remove(log_path);
    } else {
      cli_test::write_file(log_path + ".tmp", foreign);
      fs::rename(log_path + ".tmp", log_path);
    }
    kill(live.pid, SIGCONT);
    EXPECT_EQ(exit_code(live.pid), 2);
    const std::string said = test::read_file(live.output);
    const std::string recovered = set_aside_path(log_path, SetAside::recovered, 1).string();
    EXPECT_NE(said.find("the session log was replaced while this session wrote it"), std::string::npos) << said;
    EXPECT_NE(said.find("kept in " + recovered), std::string::npos) << said;
    // Every event written, the ones after the replacement too, and the other program's file untouched.
    const std::string copy = test::read_file(recovered);
    EXPECT_EQ(copy.substr(0, written.size()), written);
    EXPECT_GT(copy.size(), written.size());
    EXPECT_EQ(read_session_record(read_event_log(recovered)).integrity.status, LogStatus::unsealed);
    if (removed) EXPECT_FALSE(fs::exists(log_path));
    else EXPECT_EQ(test::read_file(log_path), foreign);

    const Child resumed = start_run(results, "", removed ? "removed-resumed" : "replaced-resumed");
    EXPECT_EQ(exit_code(resumed.pid), 0) << test::read_file(resumed.output);
    EXPECT_NE(test::read_file(resumed.output).find("resumed from events.jsonl.recovered-1"), std::string::npos)
        << test::read_file(resumed.output);
    EXPECT_FALSE(fs::exists(recovered));
    const fs::path replaced = set_aside_path(log_path, SetAside::replaced, 1);
    if (removed) EXPECT_FALSE(fs::exists(replaced));
    else EXPECT_EQ(test::read_file(replaced), foreign);
    expect_one_whole_session(log_path);
    EXPECT_EQ(test::trial_summary(log_path), whole_trials);
  }

  // Written over in place (the same file: cp onto it, a shell's >): no copy can hold what the other
  // program overwrote, so the session stops at its next event, says so, and leaves the file as it is.
  const fs::path results = root / "overwritten";
  const std::string log_path = session_log_path(results.string(), "tiny_pair", "R1");
  const Child live = start_run(results, "trial_end:2", "overwritten");
  ASSERT_TRUE(wait_until_stopped(live.pid)) << test::read_file(live.output);
  const std::string foreign = "{\"written_by\":\"another program\"}\n";
  {
    std::ofstream over(log_path, std::ios::binary | std::ios::trunc);
    over << foreign;
  }
  kill(live.pid, SIGCONT);
  EXPECT_EQ(exit_code(live.pid), 2);
  const std::string said = test::read_file(live.output);
  EXPECT_NE(said.find(log_path + ": another program wrote into the session log while this session wrote it"),
            std::string::npos)
      << said;
  EXPECT_EQ(test::read_file(log_path).substr(0, foreign.size()), foreign);  // not cut back by the session
}

}  // namespace
}  // namespace fovlab
