#include "protocols/session/replay.h"

#include <chrono>
#include <filesystem>
#include <algorithm>
#include <map>

#include "analysis/image_metrics/image_metrics.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "protocols/log/session_record.h"
#include "protocols/presentation/frame_io.h"
#include "protocols/observer/simulated_observer.h"
#include "protocols/schedule/study_plan.h"
#include "protocols/session/session_header.h"
#include "protocols/stimuli/stimulus_library.h"
#include "renderer/vk/context.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

std::string frame_file_name(int stimulus, int frame) {
  return "stimulus" + std::to_string(stimulus) + "_frame" + std::to_string(frame) + ".png";
}

class Differences {
 public:
  Differences(ReplayOutcome& outcome, int limit) : outcome_(outcome), limit_(limit) {}
  void add(const std::string& where, const std::string& what) {
    if (static_cast<int>(outcome_.differences.size()) < limit_) outcome_.differences.push_back(where + ": " + what);
    ++outcome_.difference_count;
  }

 private:
  ReplayOutcome& outcome_;
  int limit_;
};

std::string line_of(const nlohmann::json& event) { return "seq " + std::to_string(event.value("seq", -1)); }

// The answers a simulated observer gives must come out the same again.
void check_observer_answers(const SimulatedObserver& observer, const StudyPlan& plan, const RecordedTrial& recorded,
                            Differences& differences) {
  const Trial& trial = plan.trials.at(static_cast<size_t>(recorded.index));
  const ProtocolKind kind = plan.config.protocol.kind;
  const std::string where = "trial " + std::to_string(recorded.index);
  int ladder_index = trial.slider_start;
  for (size_t i = 0; i < recorded.responses.size(); ++i) {
    const nlohmann::json& response = recorded.responses[i];
    const int step = response.value("step", 0);
    ObserverAnswer expected;
    if (kind == ProtocolKind::ramp) expected = observer.answer_ramp_step(trial, step);
    else if (kind == ProtocolKind::slider) expected = observer.answer_slider(trial, step, ladder_index);
    else expected = observer.answer_comparison(trial);
    const std::string logged = response.value("answer", "");
    if (logged != expected.answer)
      differences.add(where + " (" + line_of(response) + ")",
                      "answer \"" + logged + "\" but the simulated observer answers \"" + expected.answer + "\"");
    if (kind == ProtocolKind::slider) ladder_index = next_ladder_index(trial, expected.answer, ladder_index);
  }
}

ReplayOutcome replay_checked(const ReplayOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  ReplayOutcome outcome;
  Differences differences(outcome, options.max_differences);
  const EventLogFile log = read_event_log(options.log_path);
  if (log.first_chain_error_line)
    differences.add(options.log_path + ":" + std::to_string(log.first_chain_error_line),
                    "the event chain breaks here (a line was edited, removed or reordered)");
  if (log.torn_tail)
    differences.add(options.log_path, "the last line is cut off (" + std::to_string(log.torn_tail->size()) +
                                          " bytes, not used); the session was interrupted and not resumed");
  const SessionRecord record = read_session_record(log);
  const nlohmann::json& header = record.header;
  const StudyConfig config = parse_study_config_text(header.value("config_toml", ""), header.value("config_path", "config.toml"));
  const StudyPlan plan = make_study_plan(config, header.value("participant", ""));
  if (header.value("session_seed", uint64_t(0)) != plan.session_seed)
    differences.add("header", "session_seed differs from the one derived from the study seed and participant");
  const nlohmann::json recorded_scenes = header.value("scene_hashes", nlohmann::json::object());
  const nlohmann::json current_scenes = scene_hashes(plan);
  if (recorded_scenes != current_scenes)
    differences.add("header", "scene files changed since the session (scene_hashes " + recorded_scenes.dump() +
                                  " now " + current_scenes.dump() + ")");

  std::optional<SimulatedObserver> observer;
  if (header.contains("observer") && header["observer"].is_object())
    observer.emplace(observer_from_json(header["observer"]), plan);

  vk::Context context(vk::ContextOptions{options.device_selector, options.validation});
  const nlohmann::json device = header.value("device", nlohmann::json::object());
  outcome.same_device = device.value("name", "") == context.description.name &&
                        device.value("driver", "") == context.description.driver &&
                        device.value("api_version", "") == context.description.api_version;
  const bool by_ssim = !options.reference_frames.empty();
  outcome.comparison = by_ssim ? "ssim" : "hash";
  if (!options.frames_out.empty()) fs::create_directories(options.frames_out);

  StimulusLibrary library(context);
  std::map<std::pair<int, int>, PreparedFrame> rendered;  // gaze-independent frames, rendered once
  const auto frame_for = [&](int stimulus, int frame, const GazeSample& gaze) -> const PreparedFrame& {
    const auto key = std::make_pair(stimulus, frame);
    auto found = rendered.find(key);
    if (found != rendered.end() && !method_depends_on_gaze(plan.stimuli[static_cast<size_t>(stimulus)].spec.method))
      return found->second;
    PreparedFrame made = library.render(plan.stimuli[static_cast<size_t>(stimulus)].spec, frame, gaze);
    ++outcome.frames_rendered;
    if (!options.frames_out.empty()) write_frame_image(fs::path(options.frames_out) / frame_file_name(stimulus, frame), made.image);
    if (by_ssim) {
      const fs::path reference_path = fs::path(options.reference_frames) / frame_file_name(stimulus, frame);
      const double value = analysis::ssim(read_image(reference_path), frame_to_image(made.image)).mean_ssim;
      outcome.lowest_ssim = std::min(outcome.lowest_ssim, value);
      if (value < options.min_ssim)
        differences.add(reference_path.string(), "SSIM " + std::to_string(value) + " below " + std::to_string(options.min_ssim));
    }
    return rendered.insert_or_assign(key, std::move(made)).first->second;
  };

  std::map<std::pair<int, int>, std::string> reference_hashes;
  const auto reference_hash = [&](int stimulus, int frame) -> const std::string& {
    const auto key = std::make_pair(stimulus, frame);
    auto found = reference_hashes.find(key);
    if (found == reference_hashes.end()) {
      const fs::path path = fs::path(options.reference_frames) / frame_file_name(stimulus, frame);
      found = reference_hashes.emplace(key, frame_hash(image_to_frame(read_image(path)))).first;
    }
    return found->second;
  };
  if (record.ended && record.end_reason == "completed" && record.trials.size() != plan.trials.size())
    differences.add("session_end", "the session says it completed, but the log holds " +
                                       std::to_string(record.trials.size()) + " of " +
                                       std::to_string(plan.trials.size()) + " trials");
  outcome.session_ended = record.ended;
  for (const RecordedTrial& recorded : record.trials) {
    ++outcome.trials;
    const std::string where = "trial " + std::to_string(recorded.index);
    if (recorded.index < 0 || recorded.index >= static_cast<int>(plan.trials.size())) {
      differences.add(where, "not a trial of the schedule (it has " + std::to_string(plan.trials.size()) + ")");
      continue;
    }
    const Trial& trial = plan.trials[static_cast<size_t>(recorded.index)];
    const nlohmann::json& start = recorded.start;
    if (start.value("sequence", nlohmann::json()) != nlohmann::json(trial.sequence) ||
        start.value("condition", "") != trial.condition || start.value("attention_check", false) != trial.attention_check)
      differences.add(where, "trial_start differs from the schedule rebuilt from the header (sequence " +
                                 start.value("sequence", nlohmann::json()).dump() + ", schedule " +
                                 nlohmann::json(trial.sequence).dump() + ")");
    const auto allowed = protocol_answers(config.protocol.kind, config.protocol.two_afc_question);
    for (const nlohmann::json& response : recorded.responses) {
      const std::string answer = response.value("answer", "");
      if (!answer.empty() && std::find(allowed.begin(), allowed.end(), answer) == allowed.end())
        differences.add(where + " (" + line_of(response) + ")", "answer \"" + answer + "\" is not an answer of this protocol");
    }
    if (observer) check_observer_answers(*observer, plan, recorded, differences);
    if (recorded.attention_check && !recorded.responses.empty()) {
      const bool correct = recorded.responses.front().value("answer", "") == identical_answer(config.protocol);
      if (recorded.attention_check->value("correct", !correct) != correct)
        differences.add(where, "attention_check.correct does not match the answer");
    }

    // The stimuli shown, in order: comparison and ramp trials show their sequence; a slider trial
    // starts with the reference and then shows ladder steps or the reference again.
    std::vector<int> shown_ids;
    for (const nlohmann::json& shown : recorded.stimuli) shown_ids.push_back(shown.value("stimulus", -1));
    if (config.protocol.kind == ProtocolKind::slider) {
      for (size_t i = 0; i < shown_ids.size(); ++i) {
        const bool on_ladder = std::find(trial.sequence.begin(), trial.sequence.end(), shown_ids[i]) != trial.sequence.end();
        if ((i == 0 && shown_ids[i] != trial.reference) || (!on_ladder && shown_ids[i] != trial.reference))
          differences.add(where, "stimulus " + std::to_string(shown_ids[i]) + " is not the reference or on the ladder");
      }
    } else if (shown_ids != trial.sequence) {
      differences.add(where, "stimuli shown " + nlohmann::json(shown_ids).dump() + ", the schedule has " +
                                 nlohmann::json(trial.sequence).dump());
    }
    const int refreshes = config.stimulus.refreshes_per_frame(config.display.refresh_hz);
    for (const nlohmann::json& shown : recorded.stimuli) {
      const int stimulus = shown.value("stimulus", -1);
      std::vector<int> expected_frames;  // every animation frame, each held `refreshes` refreshes
      for (int frame = 0; frame < config.stimulus.frame_count(); ++frame)
        for (int refresh = 0; refresh < refreshes; ++refresh) expected_frames.push_back(frame);
      if (shown.value("frame", nlohmann::json::array()) != nlohmann::json(expected_frames))
        differences.add(where + " (" + line_of(shown) + ")", "the frames shown are not every frame of the stimulus, " +
                                                                 std::to_string(refreshes) + " refreshes each");
      if (stimulus < 0 || stimulus >= static_cast<int>(plan.stimuli.size())) {
        differences.add(where + " (" + line_of(shown) + ")", "stimulus id " + std::to_string(stimulus) + " not in the plan");
        continue;
      }
      const nlohmann::json frames = shown.value("frame", nlohmann::json::array());
      const nlohmann::json hashes = shown.value("hash", nlohmann::json::array());
      const nlohmann::json gaze = shown.value("gaze", nlohmann::json::array());
      if (frames.size() != hashes.size() || frames.size() != gaze.size()) {
        differences.add(where + " (" + line_of(shown) + ")", "frame, hash and gaze arrays differ in length");
        continue;
      }
      for (size_t i = 0; i < frames.size(); ++i) {
        GazeSample sample;
        sample.x_px = gaze[i].at(0).get<double>();
        sample.y_px = gaze[i].at(1).get<double>();
        const int frame = frames[i].get<int>();
        if (frame < 0 || frame >= plan.stimuli[static_cast<size_t>(stimulus)].spec.frame_count) {
          differences.add(where + " (" + line_of(shown) + ")", "frame " + std::to_string(frame) + " out of range");
          break;
        }
        const PreparedFrame& again = frame_for(stimulus, frame, sample);
        ++outcome.presents_checked;
        if (by_ssim && reference_hash(stimulus, frame) != hashes[i].get<std::string>())
          differences.add(where + " (" + line_of(shown) + ") stimulus " + std::to_string(stimulus) + " frame " +
                              std::to_string(frame),
                          "the reference frame's hash is not the logged one (frames from another session?)");
        if (!by_ssim && again.hash != hashes[i].get<std::string>())
          differences.add(where + " (" + line_of(shown) + ") stimulus " + std::to_string(stimulus) + " frame " +
                              std::to_string(frame),
                          "frame hash " + hashes[i].get<std::string>() + " logged, " + again.hash + " rendered" +
                              (outcome.same_device ? "" : " (recorded on another device: use --reference-frames)"));
      }
    }
  }
  outcome.render_s = library.render_seconds();
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (context.validation_message_count() > 0)
    throw std::runtime_error("the Vulkan validation layer reported messages during replay (see stderr)");
  return outcome;
}

}  // namespace

ReplayOutcome replay_session(const ReplayOptions& options) {
  try {
    return replay_checked(options);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(options.log_path + ": an event has a field of the wrong type (" + error.what() + ")");
  }
}

}  // namespace fovlab
