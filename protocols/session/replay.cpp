#include "protocols/session/replay.h"

#include <chrono>
#include <filesystem>
#include <algorithm>
#include <map>
#include <string>

#include "metrics/image_metrics.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "study/log/log_consistency.h"
#include "study/log/log_integrity.h"
#include "study/log/session_record.h"
#include "display/frame_io.h"
#include "protocols/observer/simulated_observer.h"
#include "study/schedule/study_plan.h"
#include "study/log/schedule_check.h"
#include "protocols/session/head_tracking.h"
#include "protocols/session/headset_views.h"
#include "protocols/session/session_header.h"
#include "protocols/stimuli/image_sequence.h"
#include "protocols/stimuli/plan_renderable.h"
#include "protocols/stimuli/stimulus_library.h"
#include "renderer/vk/context.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

// A headset session's right eye's frames carry "_right" before the extension; the left eye's, and a
// desktop session's, none.
std::string eye_suffix(size_t eye) { return eye == 0 ? "" : "_right"; }

std::string frame_file_name(int stimulus, int frame, size_t eye) {
  return "stimulus" + std::to_string(stimulus) + "_frame" + std::to_string(frame) + eye_suffix(eye) + ".png";
}

// A gaze-dependent stimulus has an image per refresh of each presentation; (trial, step) names
// the presentation (slider steps count every showing).
std::string image_file_name(int trial, int step, int stimulus, int image, size_t eye) {
  return "trial" + std::to_string(trial) + "_step" + std::to_string(step) + "_stimulus" + std::to_string(stimulus) +
         "_image" + std::to_string(image) + eye_suffix(eye) + ".png";
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

// Where the stimulus JSON this build makes differs from the one the log recorded, as "key.key: A by
// this build's reading of config_toml, the log records B" (numbers compare by value); "" when they
// agree. A key the log lacks is not a difference: a parameter added later without
// omitted_at_default (the sampling models' resample) is missing from older logs at its default.
std::string first_difference(const nlohmann::json& made, const nlohmann::json& recorded, const std::string& path = "") {
  if (made == recorded) return "";
  const auto describe = [](const std::string& where, const nlohmann::json* made_value, const nlohmann::json& logged) {
    return (where.empty() ? "" : where + ": ") + (made_value ? made_value->dump() : std::string("none")) +
           " by this build's reading of config_toml, the log records " + logged.dump();
  };
  if (!made.is_object() || !recorded.is_object()) return describe(path, &made, recorded);
  for (const auto& [key, logged] : recorded.items()) {
    const std::string where = path.empty() ? key : path + "." + key;
    if (!made.contains(key)) return describe(where, nullptr, logged);
    if (std::string difference = first_difference(made[key], logged, where); !difference.empty()) return difference;
  }
  return "";
}

std::string line_of(const EventStamp& stamp) { return "seq " + std::to_string(stamp.seq.value_or(-1)); }

// The answers a simulated observer gives must come out the same again.
void check_observer_answers(const SimulatedObserver& observer, const StudyPlan& plan, const Trial& trial,
                            const RecordedTrial& recorded, Differences& differences) {
  const ProtocolKind kind = plan.config.protocol.kind;
  const std::string where = "trial " + std::to_string(recorded.index);
  int ladder_index = trial.slider_start;
  for (size_t i = 0; i < recorded.responses.size(); ++i) {
    const ResponseEvent& response = recorded.responses[i];
    const int step = response.step;
    ObserverAnswer expected;
    if (kind == ProtocolKind::ramp) expected = observer.answer_ramp_step(trial, step);
    else if (kind == ProtocolKind::slider) expected = observer.answer_slider(trial, step, ladder_index);
    else expected = observer.answer_comparison(trial);
    const std::string& logged = response.answer;
    if (logged != expected.answer)
      differences.add(where + " (" + line_of(response.stamp) + ")",
                      "answer \"" + logged + "\" but the simulated observer answers \"" + expected.answer + "\"");
    if (kind == ProtocolKind::slider) ladder_index = next_ladder_index(trial, expected.answer, ladder_index);
  }
}

ReplayOutcome replay_checked(const ReplayOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  ReplayOutcome outcome;
  Differences differences(outcome, options.max_differences);
  const EventLogFile log = read_event_log(options.log_path);
  const std::optional<LabKey> lab_key = read_optional_lab_key(options.lab_key_path);
  const SessionRecord record = read_session_record(log, lab_key ? &*lab_key : nullptr);
  outcome.integrity = record.integrity;
  if (record.integrity.status == LogStatus::broken)
    differences.add(options.log_path + ":" + std::to_string(record.integrity.line), record.integrity.reason);
  if (log.torn_tail)
    differences.add(options.log_path, "the last line is cut off (" + std::to_string(log.torn_tail->size()) +
                                          " bytes, not used); the session was interrupted and not resumed");
  SessionHeaderEvent header;
  try {
    header = parse_session_header(record.header);
  } catch (const InputError& error) {
    throw InputError(options.log_path + ":1: " + error.what());
  }
  if (!record.header.contains(log_keys::config_path)) header.config_path = "config.toml";
  const SceneCatalog scenes = renderer_scene_catalog();
  // The text is the log's: a fault in it is named by the log's path (its scene files are still
  // found beside the config it was run with, config_path).
  const StudyConfig config = [&] {
    try {
      return parse_logged_study_config(header.config_toml, header.config_path, header.schema_version, &scenes,
                                       header.conditions_csv);
    } catch (const InputError& error) {
      std::string message = error.what();
      const std::string logged = options.log_path + ":1: config_toml (of " + header.config_path + ")";
      if (message.rfind(header.config_path, 0) == 0) message.replace(0, header.config_path.size(), logged);
      else message = logged + ": " + message;
      throw InputError(message);
    }
  }();
  // The header's own claims about its config: the name, hash and seed must be those of the text it
  // holds (the same checks as export and analyze, log_consistency.h).
  for (const std::string& difference : header_differences(record.header, config)) differences.add("header", difference);
  const StudyPlan plan = make_study_plan(config, header.participant);
  // A session of the lab's images replays only on the images it showed: each one's SHA-256 (schema 9).
  const std::string image_hashes_source = options.log_path + ":1: image_hashes";
  const nlohmann::json current_images = [&] {
    try {
      return plan_image_hashes(plan);
    } catch (const InputError& error) {
      throw InputError(image_hashes_source + ": " + error.what());
    }
  }();
  check_image_hashes(header.image_hashes, current_images, image_hashes_source);
  // What no session could have rendered is refused before the device is opened, as run refuses it.
  check_plan_renderable(plan, options.log_path + ":1: config_toml (of " + header.config_path + ")", PlanUse::replay);
  // The stimuli this build makes of config_toml must be those the session recorded: a parameter read
  // otherwise (a default that changed, read without the log's schema) renders other frames. Schema
  // 3 and later record them as stimuli_json does (schema 1-2: older keys and numeric choices).
  if (header.schema_version >= 3) {
    const nlohmann::json made = stimuli_json(plan);
    const nlohmann::json& recorded = header.stimuli;
    if (!recorded.is_array() || recorded.size() != made.size())
      differences.add("header", "stimuli: the log records " +
                                    std::to_string(recorded.is_array() ? recorded.size() : 0) +
                                    ", its config_toml makes " + std::to_string(made.size()));
    else
      for (size_t id = 0; id < made.size(); ++id)
        if (const std::string difference = first_difference(made[id], recorded[id]); !difference.empty())
          differences.add("header", "stimulus " + std::to_string(id) + ": " + difference);
  }
  const nlohmann::json& recorded_scenes = header.scene_hashes;
  const nlohmann::json current_scenes = scene_hashes(plan, current_images);
  if (recorded_scenes != current_scenes)
    differences.add("header", "scene files changed since the session (scene_hashes " + recorded_scenes.dump() +
                                  " now " + current_scenes.dump() + ")");

  std::optional<SimulatedObserver> observer;
  if (header.observer.is_object()) observer.emplace(observer_from_json(header.observer), plan);

  vk::Context context(vk::ContextOptions{options.device_selector, options.validation});
  const nlohmann::json& device = header.device;
  outcome.same_device = device.value("name", "") == context.description.name &&
                        device.value("driver", "") == context.description.driver &&
                        device.value("api_version", "") == context.description.api_version;
  const bool by_ssim = !options.reference_frames.empty();
  outcome.comparison = by_ssim ? "ssim" : "hash";
  if (!options.frames_out.empty()) fs::create_directories(options.frames_out);

  // One view on a desktop; in a headset (schema 11) the two eyes, each rendered from its logged view.
  // Frames of gaze-independent stimuli are rendered once a view, by (stimulus, frame). Every image of
  // a gaze-dependent stimulus (fipr) is rendered again, in the order of its presentation, with its
  // logged gaze and its position in the stimulus event's arrays as the presentation's image index
  // (SessionRun::present_stimulus), so the periphery refresh reuses the same previous images.
  struct ViewReplay {
    StimulusLibrary library;
    std::map<std::pair<int, int>, PreparedFrame> rendered;
    PreparedFrame live;
  };
  std::vector<std::unique_ptr<ViewReplay>> views;
  // Head-tracked (schema 12): every refresh is rendered from its logged head_pose, as the session did.
  bool head_tracked = false;
  if (header.headset.is_null()) {
    views.emplace_back(new ViewReplay{StimulusLibrary(context, options.cache_dir), {}, {}});
  } else {
    const HeadsetViews headset = headset_views_from_json(header.headset, options.log_path + ":1");
    head_tracked = headset.view_model == HeadsetViewModel::head_tracked;
    for (const EyeView& eye : headset.eyes)
      views.emplace_back(new ViewReplay{StimulusLibrary(context, options.cache_dir, eye, head_tracked), {}, {}});
  }
  const auto image_for = [&](size_t view, int stimulus, const StimulusImage& image,
                             const std::string& file_name) -> const PreparedFrame& {
    ViewReplay& replaying = *views[view];
    const StimulusSpec& spec = plan.stimuli[static_cast<size_t>(stimulus)].spec;
    const bool gaze_dependent = describe(spec.method()).depends_on_gaze || image.head.has_value();
    const auto key = std::make_pair(stimulus, image.frame);
    if (!gaze_dependent) {
      const auto found = replaying.rendered.find(key);
      if (found != replaying.rendered.end()) return found->second;
    }
    PreparedFrame made = replaying.library.render(spec, image);
    ++outcome.frames_rendered;
    if (!options.frames_out.empty()) write_frame_image(fs::path(options.frames_out) / file_name, made.image);
    if (by_ssim) {
      const fs::path reference_path = fs::path(options.reference_frames) / file_name;
      const double value = metrics::ssim(read_image(reference_path), frame_to_image(made.image)).mean_ssim;
      outcome.lowest_ssim = std::min(outcome.lowest_ssim, value);
      if (value < options.min_ssim)
        differences.add(reference_path.string(),
                        "SSIM " + std::to_string(value) + " below " + std::to_string(options.min_ssim));
    }
    if (gaze_dependent) {
      replaying.live = std::move(made);
      return replaying.live;
    }
    return replaying.rendered.emplace(key, std::move(made)).first->second;
  };

  std::map<std::string, std::string> reference_hashes;  // by file name
  const auto reference_hash = [&](const std::string& file_name) -> const std::string& {
    auto found = reference_hashes.find(file_name);
    if (found == reference_hashes.end()) {
      const fs::path path = fs::path(options.reference_frames) / file_name;
      found = reference_hashes.emplace(file_name, frame_hash(image_to_frame(read_image(path)))).first;
    }
    return found->second;
  };
  // Every trial against the schedule, each adaptive one at the level its track derives from the
  // answers logged before it.
  const ScheduleCheck schedule = check_log_against_schedule(record, plan);
  for (const std::string& difference : schedule.differences) {
    const size_t colon = difference.find(": ");
    differences.add(difference.substr(0, colon), difference.substr(colon + 2));
  }
  if (record.ended && record.end_reason == "completed" && !schedule.schedule_done)
    differences.add("session_end", "the session says it completed, but the log holds " +
                                       std::to_string(record.trials.size()) + " of " +
                                       std::to_string(plan.trials.size()) + " trials and the schedule runs more");
  outcome.session_ended = record.ended;
  for (size_t position = 0; position < record.trials.size(); ++position) {
    const RecordedTrial& recorded = record.trials[position];
    ++outcome.trials;
    const std::string where = "trial " + std::to_string(recorded.index);
    if (!schedule.presented[position]) continue;  // a difference already
    const Trial& trial = *schedule.presented[position];
    const auto allowed = protocol_answers(config.protocol.kind, config.protocol.two_afc_question);
    for (const ResponseEvent& response : recorded.responses) {
      const std::string& answer = response.answer;
      if (!answer.empty() && std::find(allowed.begin(), allowed.end(), answer) == allowed.end())
        differences.add(where + " (" + line_of(response.stamp) + ")",
                        "answer \"" + answer + "\" is not an answer of this protocol");
    }
    if (observer) check_observer_answers(*observer, plan, trial, recorded, differences);
    if (recorded.attention_check && !recorded.responses.empty()) {
      const bool correct = recorded.responses.front().answer == identical_answer(config.protocol);
      if (recorded.attention_check->correct != correct)
        differences.add(where, "attention_check.correct does not match the answer");
    }

    // The stimuli shown, in order: comparison and ramp trials show their sequence; a slider trial
    // starts with the reference and then shows ladder steps or the reference again.
    std::vector<int> shown_ids;
    for (const StimulusEvent& shown : recorded.stimuli) shown_ids.push_back(shown.stimulus);
    if (config.protocol.kind == ProtocolKind::slider) {
      for (size_t i = 0; i < shown_ids.size(); ++i) {
        const bool on_ladder =
            std::find(trial.sequence.begin(), trial.sequence.end(), shown_ids[i]) != trial.sequence.end();
        if ((i == 0 && shown_ids[i] != trial.reference) || (!on_ladder && shown_ids[i] != trial.reference))
          differences.add(where, "stimulus " + std::to_string(shown_ids[i]) + " is not the reference or on the ladder");
      }
    } else if (shown_ids != trial.sequence) {
      differences.add(where, "stimuli shown " + nlohmann::json(shown_ids).dump() + ", the schedule has " +
                                 nlohmann::json(trial.sequence).dump());
    }
    const int refreshes = config.stimulus.refreshes_per_frame(config.display.refresh_hz);
    for (const StimulusEvent& shown : recorded.stimuli) {
      const int stimulus = shown.stimulus;
      const std::string line = line_of(shown.stamp);
      std::vector<int> expected_frames;  // every animation frame, each held `refreshes` refreshes
      for (int frame = 0; frame < config.stimulus.frame_count(); ++frame)
        for (int refresh = 0; refresh < refreshes; ++refresh) expected_frames.push_back(frame);
      if (shown.frame != expected_frames)
        differences.add(where + " (" + line + ")", "the frames shown are not every frame of the stimulus, " +
                                                       std::to_string(refreshes) + " refreshes each");
      if (stimulus < 0 || stimulus >= static_cast<int>(plan.stimuli.size())) {
        differences.add(where + " (" + line + ")", "stimulus id " + std::to_string(stimulus) + " not in the plan");
        continue;
      }
      const std::vector<int>& frames = shown.frame;
      // Each view's hashes and gaze: the event's own, and in a headset the right eye's beside them.
      const bool headset_event = shown.right_eye_hash || shown.right_eye_gaze;
      if (headset_event != (views.size() == 2)) {
        differences.add(where + " (" + line + ")", views.size() == 2
                                                       ? "a headset session's stimulus without the right eye's hashes"
                                                       : "right_eye_hash or right_eye_gaze in a session of one view");
        continue;
      }
      const std::vector<std::string> no_hashes;
      const std::vector<std::array<double, 2>> no_gaze;
      const std::array<const std::vector<std::string>*, 2> view_hashes{
          &shown.hash, shown.right_eye_hash ? &*shown.right_eye_hash : &no_hashes};
      const std::array<const std::vector<std::array<double, 2>>*, 2> view_gaze{
          &shown.gaze, shown.right_eye_gaze ? &*shown.right_eye_gaze : &no_gaze};
      bool lengths_agree = true;
      for (size_t view = 0; view < views.size(); ++view)
        lengths_agree =
            lengths_agree && frames.size() == view_hashes[view]->size() && frames.size() == view_gaze[view]->size();
      if (!lengths_agree) {
        differences.add(where + " (" + line + ")", "frame, hash and gaze arrays differ in length");
        continue;
      }
      // Head-tracked: one head pose a refresh, read back as rendered (head_tracking.h).
      std::vector<HeadPose> head_poses;
      if (shown.head_pose.has_value() != head_tracked) {
        differences.add(where + " (" + line + ")", head_tracked ? "a head-tracked session's stimulus without head_pose"
                                                                : "head_pose in a session that is not head-tracked");
        continue;
      }
      if (head_tracked) {
        std::string error;
        for (const std::array<double, 7>& entry : *shown.head_pose) {
          const std::optional<HeadPose> pose = head_pose_of_entry(entry, error);
          if (!pose) break;
          head_poses.push_back(*pose);
        }
        if (!error.empty() || head_poses.size() != frames.size()) {
          differences.add(where + " (" + line + ")",
                          "head_pose: " + (error.empty() ? "one entry a refresh expected, as frame's" : error));
          continue;
        }
      }
      const bool gaze_dependent =
          describe(plan.stimuli[static_cast<size_t>(stimulus)].spec.method()).depends_on_gaze || head_tracked;
      for (size_t i = 0; i < frames.size(); ++i) {
        const int frame = frames[i];
        if (frame < 0 || frame >= plan.stimuli[static_cast<size_t>(stimulus)].spec.frame_count) {
          differences.add(where + " (" + line + ")", "frame " + std::to_string(frame) + " out of range");
          break;
        }
        for (size_t view = 0; view < views.size(); ++view) {
          const std::vector<std::string>& hashes = *view_hashes[view];
          StimulusImage image;
          image.image_index = static_cast<int>(i);
          image.gaze.x_px = (*view_gaze[view])[i][0];
          image.gaze.y_px = (*view_gaze[view])[i][1];
          image.frame = frame;
          if (head_tracked) image.head = head_poses[i];
          const std::string file_name =
              gaze_dependent ? image_file_name(recorded.index, shown.step, stimulus, image.image_index, view)
                             : frame_file_name(stimulus, frame, view);
          const PreparedFrame& again = image_for(view, stimulus, image, file_name);
          ++outcome.presents_checked;
          const std::string what = where + " (" + line + ") stimulus " + std::to_string(stimulus) + " frame " +
                                   std::to_string(frame) + (gaze_dependent ? " image " + std::to_string(i) : "") +
                                   (views.size() == 2 ? (view == 0 ? " left eye" : " right eye") : "");
          if (by_ssim && reference_hash(file_name) != hashes[i])
            differences.add(what, "the reference frame's hash is not the logged one (frames from another session?)");
          if (!by_ssim && again.hash != hashes[i])
            differences.add(what, "frame hash " + hashes[i] + " logged, " + again.hash + " rendered" +
                                      (!outcome.same_device ? " (recorded on another device: use --reference-frames)"
                                       : header.schema_version < 4
                                           ? " (a schema " + std::to_string(header.schema_version) +
                                                 " log: its sphere-traced frames were sRGB-encoded on the CPU, which "
                                                 "may round a channel the other way; use --reference-frames)"
                                           : ""));
        }
      }
    }
  }
  for (const auto& view : views) outcome.render_s += view->library.render_seconds();
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
