// The seeds' headset studies run end to end in the test runtime by a participant on the controller:
// `fovlab run` as a human session (no --observer) in a child process, whose presses come from this
// test. The test follows the session's log as it is written (fsync'd per event), and whenever the
// session waits for a press (the log's last event says so) asks the product's own
// SimulatedObserver, made as `--observer simulated` makes it (parse_observer_spec on the same plan:
// the same seed and parameters), for its answer, and presses the Xbox controller's button for that
// answer's key through the test runtime's press queue (FOVLAB_TEST_XR_PRESS_QUEUE). The answers then
// equal a `--observer simulated` run's trial by trial, which they can only do by going through the
// runtime's actions, the presenter and the protocol's keys; the log replays and analyzes to the
// simulated run's thresholds.
//
// The product learns nothing of this: the session is a participant's, the observer is consulted
// here, and only the test runtime knows the queue.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "protocols/observer/simulated_observer.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"
#include "tests/app/cli_test_support.h"
#include "tests/app/headset_study_support.h"
#include "tests/display/openxr/openxr_test_support.h"
#include "tests/support/fovlab_child.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using cli_test::CommandResult;
using test::LogFollower;

// The Xbox controller's button of each answer key, as docs/hmd.md's table binds them. Written out
// here rather than taken from display/openxr: a binding the product got wrong fails this test.
const std::map<std::string, std::string>& xbox_buttons() {
  static const std::map<std::string, std::string> buttons{
      {"pad_a", "/user/gamepad/input/a/click"},
      {"pad_b", "/user/gamepad/input/b/click"},
      {"pad_x", "/user/gamepad/input/x/click"},
      {"pad_y", "/user/gamepad/input/y/click"},
      {"pad_left", "/user/gamepad/input/dpad_left/click"},
      {"pad_right", "/user/gamepad/input/dpad_right/click"},
      {"pad_up", "/user/gamepad/input/dpad_up/click"},
      {"pad_down", "/user/gamepad/input/dpad_down/click"},
      {"pad_start", "/user/gamepad/input/menu/click"},
      {"pad_back", "/user/gamepad/input/view/click"},
      {"pad_lb", "/user/gamepad/input/shoulder_left/click"},
      {"pad_rb", "/user/gamepad/input/shoulder_right/click"},
  };
  return buttons;
}

// The button a participant presses for `answer`: its first gamepad key in the config's keys.
std::string button_for(const QuestionConfig& question, const std::string& answer) {
  for (const auto& [name, keys] : question.answers) {
    if (name != answer) continue;
    for (const std::string& key : keys)
      if (xbox_buttons().count(key)) return xbox_buttons().at(key);
  }
  ADD_FAILURE() << "no gamepad key for the answer \"" << answer << "\"";
  return {};
}

// A participant who is the simulated observer: after each event of the log, the button the session
// now waits for, or "" when it waits for none.
class ControllerParticipant {
 public:
  explicit ControllerParticipant(const StudyPlan& plan)
      : plan_(plan), observer_(parse_observer_spec("simulated", plan), plan) {}

  std::string button_after(const nlohmann::json& event) {
    const StudyConfig& config = plan_.config;
    const QuestionConfig& question = config.protocol.question;
    const std::string kind = event.value("event", "");
    // The instructions (of a new session or a resumed one), the attention-check break's end and the
    // exclusion screen take any answer key: the first answer's.
    const std::string any_key = button_for(question, question.answers.front().first);
    if (kind == "session_header" || kind == "session_resumed") return any_key;
    if (kind == "attention_check" && !event.value("correct", true) &&
        event.value("errors", 0) < config.attention.max_errors && config.attention.break_s > 0)
      return any_key;
    if (kind == "session_end" && event.value("reason", "") == "excluded") return any_key;
    if (kind == "trial_start") sequence_length_[event["trial"].get<int>()] = static_cast<int>(event["sequence"].size());
    if (kind != "stimulus") return {};
    const int trial_index = event["trial"].get<int>(), step = event["step"].get<int>();
    const Trial& trial = plan_.trials.at(static_cast<size_t>(trial_index));
    EXPECT_EQ(trial.index, trial_index);
    switch (config.protocol.kind) {
      case ProtocolKind::ramp:
        return step > 0 ? button_for(question, observer_.answer_ramp_step(trial, step).answer) : std::string();
      case ProtocolKind::slider:
        ADD_FAILURE() << "slider studies are not answered here";
        return {};
      default:  // comparisons: one answer after the trial's last stimulus
        return step + 1 == sequence_length_.at(trial_index)
                   ? button_for(question, observer_.answer_comparison(trial).answer)
                   : std::string();
    }
  }

 private:
  const StudyPlan& plan_;
  SimulatedObserver observer_;
  std::map<int, int> sequence_length_;  // by trial: its stimuli
};

// One answer of a log: the trial, the step answered, the answer.
using LoggedAnswer = std::tuple<int, int, std::string>;

std::vector<nlohmann::json> events_of(const fs::path& log) {
  std::vector<nlohmann::json> events;
  std::ifstream lines(log);
  for (std::string line; std::getline(lines, line);) events.push_back(nlohmann::json::parse(line));
  return events;
}

std::vector<LoggedAnswer> answers_of(const fs::path& log) {
  std::vector<LoggedAnswer> answers;
  for (const nlohmann::json& event : events_of(log))
    if (event.value("event", "") == "response")
      answers.emplace_back(event["trial"].get<int>(), event["step"].get<int>(), event.value("answer", ""));
  return answers;
}

// What thresholds.json says of the study's answers, without what tells the two runs apart (their
// observers, logs, timing).
nlohmann::json analysed_answers(const fs::path& report) {
  std::ifstream file(report / "thresholds.json");
  const nlohmann::json analysis = nlohmann::json::parse(file);
  nlohmann::json kept;
  for (const char* key :
       {"headlines", "thresholds", "fits", "not_fitted", "conditions", "rating_grid", "preference_table"})
    kept[key] = analysis.value(key, nlohmann::json());
  for (const nlohmann::json& participant : analysis["participants"])
    kept["participants"].push_back(participant["thresholds"]);
  return kept;
}

class ControllerObserver : public test::OpenXrTest {
 protected:
  // experiments/<name>.toml at 64x72 an eye, one repeat, its first block only, and the lines of
  // `lines` ("key = value") in place of its own: a few short trials of the published protocol.
  fs::path cut_experiment(const std::string& name, std::vector<std::string> lines) {
    std::ifstream experiment(std::string(FOVLAB_SOURCE_DIR) + "/experiments/" + name + ".toml");
    std::string text = (std::stringstream() << experiment.rdbuf()).str();
    lines.insert(lines.end(), {"eye_width_px = 64", "eye_height_px = 72", "repeats = 1"});
    for (const std::string& line : lines) {
      const std::string key = "\n" + line.substr(0, line.find(" = ") + 3);
      const size_t at = text.find(key);
      EXPECT_NE(at, std::string::npos) << key;
      if (at != std::string::npos) text.replace(at + 1, text.find('\n', at + 1) - at - 1, line);
    }
    const size_t second_block = text.find("[[block]]", text.find("[[block]]") + 1);
    if (second_block != std::string::npos) text.erase(second_block);
    return cli_test::write_file(scratch_.path() / (name + ".toml"), text);
  }

  // `fovlab run` as a participant's session, answered on the controller by the simulated observer
  // through the press queue; returns its exit code (-1: it did not end within the limit).
  int run_answering_on_the_controller(const fs::path& config_path, const fs::path& results) {
    const StudyConfig config = parse_study_config_file(config_path.string(), renderer_scene_catalog());
    const StudyPlan plan = make_study_plan(config, "P01");
    ControllerParticipant participant(plan);
    const fs::path queue = scratch_.path() / "presses.txt";
    std::ofstream(queue).close();
    const test::ScopedEnvironment queued("FOVLAB_TEST_XR_PRESS_QUEUE", queue.string());
    const pid_t pid = test::start_fovlab(
        {"run", config_path.string(), "--participant", "P01", "--results", results.string()}, "", output_);
    LogFollower log(results / config.name / "P01" / "events.jsonl");
    // A stale press (given again) reaches the next trial before its question appears, and is dropped there.
    return test::answer_while_it_runs(
        pid, log, std::chrono::seconds(500), [&](const nlohmann::json& event) { return participant.button_after(event); },
        [&](const std::string& button) { std::ofstream(queue, std::ios::app) << button << "\n"; });
  }

  // The study run twice with the headset's eye gaze (the test runtime's, straight ahead): by a
  // participant on the controller and by --observer simulated; the answers, the replay and the
  // analysis compared.
  void expect_the_controller_answers_as_the_simulated_observer(const fs::path& config) {
    const std::string study = parse_study_config_file(config.string(), renderer_scene_catalog()).name;
    const fs::path simulated_results = scratch_.path() / "simulated", human_results = scratch_.path() / "human";
    const CommandResult simulated = cli_test::run("run " + config.string() + " --participant P01 --results " +
                                                  simulated_results.string() + " --observer simulated </dev/null");
    ASSERT_EQ(simulated.exit_code, 0) << simulated.err;
    ASSERT_EQ(run_answering_on_the_controller(config, human_results), 0) << cli_test::read_all(output_);

    const fs::path simulated_log = simulated_results / study / "P01" / "events.jsonl";
    const fs::path human_log = human_results / study / "P01" / "events.jsonl";
    const std::vector<nlohmann::json> events = events_of(human_log);
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.front().value("observer", nlohmann::json()), "human") << events.front().dump();
    EXPECT_TRUE(events.front().contains("headset"));
    const std::vector<LoggedAnswer> expected = answers_of(simulated_log);
    EXPECT_GE(expected.size(), 3u) << "a few trials";
    EXPECT_EQ(answers_of(human_log), expected) << "the controller's answers, trial by trial";
    int responses = 0;
    for (const nlohmann::json& event : events) {
      const std::string kind = event.value("event", "");
      if (kind == "instructions") {
        EXPECT_GT(event.value("shown_s", 0.0), 0.0) << event.dump();
      }
      if (kind != "response") continue;
      ++responses;
      EXPECT_EQ(event.value("key", "").rfind("pad_", 0), 0u) << event.dump();
      EXPECT_GT(event.value("rt_s", 0.0), 0.0) << event.dump();
    }
    EXPECT_EQ(responses, static_cast<int>(expected.size()));
    EXPECT_EQ(events.back().value("event", ""), "seal");

    const CommandResult replayed = cli_test::run("replay " + human_log.string() + " --verify");
    EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
    EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;
    const fs::path human_report = scratch_.path() / "human_report",
                   simulated_report = scratch_.path() / "simulated_report";
    const CommandResult analysed =
        cli_test::run("analyze " + (human_results / study).string() + " --out " + human_report.string());
    ASSERT_EQ(analysed.exit_code, 0) << analysed.err;
    const CommandResult analysed_simulated =
        cli_test::run("analyze " + (simulated_results / study).string() + " --out " + simulated_report.string());
    ASSERT_EQ(analysed_simulated.exit_code, 0) << analysed_simulated.err;
    EXPECT_EQ(analysed_answers(human_report), analysed_answers(simulated_report));
    // The report says where the session ran: the headset's runtime and each eye's size.
    const std::string page = cli_test::read_all(human_report / "report.html");
    EXPECT_NE(page.find("<h2 id=\"headset\">Headset</h2>"), std::string::npos);
    EXPECT_NE(page.find("<td>fovlab test runtime 0.1.0</td><td>64 x 72</td>"), std::string::npos);
  }

  fs::path output_ = scratch_.path() / "human_run.txt";
};

// The FIPR main study of Polychronakis et al. 2023 in the headset (2AFC "same?", pad_a / pad_b).
TEST_F(ControllerObserver, TheFiprMainHeadsetStudyAnsweredOnTheControllerMatchesTheSimulatedObserver) {
  expect_the_controller_answers_as_the_simulated_observer(
      cut_experiment("fipr_main_hmd", {"duration_s = 0.1", "values = [2.5, 15]"}));
}

// The RMFR rating study of Ye et al. 2022 in the headset (ratings 1-3 on pad_b, pad_y, pad_a, with
// its attention checks).
TEST_F(ControllerObserver, TheRmfrHeadsetStudyAnsweredOnTheControllerMatchesTheSimulatedObserver) {
  expect_the_controller_answers_as_the_simulated_observer(
      cut_experiment("rmfr_sigma_hmd", {"duration_s = 0.2", "frames_per_second = 10", "values = [1.4, 2.8]"}));
}

}  // namespace
}  // namespace fovlab
