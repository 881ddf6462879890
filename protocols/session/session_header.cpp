#include "protocols/session/session_header.h"

#include <map>
#include <stdexcept>
#include <set>

#include "core/content_hash.h"
#include "core/input_error.h"
#include "study/log/event_log.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/prerender/path_scene_source.h"
#include "renderer/scene/scene_source.h"
#include "renderer/volume/volume_scene.h"
#include "renderer/vk/context.h"

#ifndef FOVLAB_VERSION
#define FOVLAB_VERSION "unknown"
#endif

namespace fovlab {

nlohmann::json gaze_source_json(GazeSourceKind kind, const std::string& spec, bool requested,
                                const GazeConfig& config) {
  nlohmann::json require = nlohmann::json::array();
  for (GazeSourceKind allowed : config.require) require.push_back(gaze_source_kind_name(allowed));
  return {{"kind", gaze_source_kind_name(kind)}, {"spec", spec}, {"requested", requested}, {"require", require}};
}

nlohmann::json gaze_validation_json(const ValidationConfig& validation) {
  if (!validation.enabled) return {{"enabled", false}};
  return {{"enabled", true},
          {"targets", validation.targets},
          {"target_offset_deg", validation.target_offset_deg},
          {"target_radius_deg", validation.target_radius_deg},
          {"target_s", validation.target_s},
          {"settle_s", validation.settle_s},
          {"max_accuracy_deg", validation.max_accuracy_deg},
          {"max_precision_deg", validation.max_precision_deg},
          {"max_attempts", validation.max_attempts},
          {"after_breaks", validation.after_breaks}};
}

nlohmann::json observer_json(const ObserverModel& model) {
  return {{"model", "logistic"},  {"threshold", model.threshold},
          {"slope", model.slope}, {"guess", model.guess},
          {"lapse", model.lapse}, {"mean_response_s", model.mean_response_s},
          {"seed", model.seed},   {"higher_is_better", model.higher_is_better}};
}

ObserverModel observer_from_json(const nlohmann::json& json) {
  try {
    ObserverModel model;
    model.threshold = json.at("threshold").get<double>();
    model.slope = json.at("slope").get<double>();
    model.guess = json.at("guess").get<double>();
    model.lapse = json.at("lapse").get<double>();
    model.mean_response_s = json.at("mean_response_s").get<double>();
    model.seed = json.at("seed").get<uint64_t>();
    model.higher_is_better = json.at("higher_is_better").get<bool>();
    return model;
  } catch (const nlohmann::json::exception& error) {
    throw InputError(std::string("session_header: observer_model: ") + error.what());
  }
}

nlohmann::json scene_hashes(const StudyPlan& plan, const nlohmann::json& image_hashes) {
  nlohmann::json hashes = nlohmann::json::object();
  std::map<std::string, SceneKind> scenes;
  for (const PlannedStimulus& stimulus : plan.stimuli)
    scenes[stimulus.spec.scene] = describe(stimulus.spec.method()).scene_kind;
  for (const auto& [scene, kind] : scenes) {
    switch (kind) {
      case SceneKind::path_traced:
        hashes[scene] = load_path_scene(scene).content_hash;
        break;
      case SceneKind::volume:
        hashes[scene] = volume_scene_hash(load_volume_scene(scene));
        break;
      case SceneKind::signed_distance:
        hashes[scene] = ContentHash().add(load_scene(scene).text).hex();
        break;
      case SceneKind::image_sequence:  // of its images' names and SHA-256s (each in image_hashes)
        if (!image_hashes.contains(scene)) throw std::logic_error("scene_hashes: no image hashes of " + scene);
        hashes[scene] = ContentHash().add(image_hashes.at(scene).dump()).hex();
        break;
    }
  }
  return hashes;
}

SessionHeaderEvent make_session_header(const SessionHeaderInputs& inputs) {
  const StudyPlan& plan = *inputs.plan;
  const StudyConfig& config = plan.config;
  const DisplayConfig& display = config.display;
  SessionHeaderEvent header;
  header.stamp.t = 0.0;
  header.schema_version = log_schema_version;
  header.fovlab_version = FOVLAB_VERSION;
  header.study = config.name;
  header.participant = plan.participant;
  header.study_seed = config.seed;
  header.session_seed = plan.session_seed;
  header.config_path = config.source_path;
  header.config_hash = config.hash;
  header.config_toml = config.source_text;
  header.conditions_csv = config.conditions_csv;
  header.protocol = protocol_name(config.protocol.kind);
  header.trial_count = static_cast<int64_t>(plan.trials.size());
  header.scene_hashes = scene_hashes(plan, inputs.image_hashes);
  header.image_hashes = inputs.image_hashes;
  header.device = {{"name", inputs.device->name},
                   {"type", inputs.device->type},
                   {"api_version", inputs.device->api_version},
                   {"driver", inputs.device->driver}};
  header.display = {{"width_px", display.width_px},
                    {"height_px", display.height_px},
                    {"refresh_hz", display.refresh_hz},
                    {"measured_refresh_hz", inputs.refresh_hz},
                    {"width_mm", display.width_mm},
                    {"height_mm", display.height_mm},
                    {"viewing_distance_mm", display.viewing_distance_mm},
                    {"fullscreen", display.fullscreen},
                    {"present_device", inputs.present_device},
                    {"frame_path", inputs.frame_path}};
  header.presenter = inputs.presenter;
  header.gaze = inputs.gaze;
  header.gaze_source = inputs.gaze_source;
  header.gaze_validation = gaze_validation_json(config.validation);
  header.observer = inputs.observer ? observer_json(*inputs.observer) : nlohmann::json("human");
  header.started_utc = inputs.started_utc;
  for (const auto& [name, value] : inputs.participant_fields) header.participant_fields[name] = value;
  header.stimuli = stimuli_json(plan);
  return header;
}

nlohmann::json stimuli_json(const StudyPlan& plan) {
  nlohmann::json stimuli = nlohmann::json::array();
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    nlohmann::json entry = to_json(stimulus.spec);
    entry["is_reference"] = stimulus.is_reference;
    entry["variant"] = stimulus.variant;
    entry["level"] = stimulus.level ? nlohmann::json(*stimulus.level) : nlohmann::json();
    stimuli.push_back(entry);
  }
  return stimuli;
}

}  // namespace fovlab
