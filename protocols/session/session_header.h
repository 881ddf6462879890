#pragma once
// The first line of every session log: everything a replay needs to rebuild the session without
// any other file (the whole config text, seeds, observer model, device, display, gaze source).
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "protocols/observer/simulated_observer.h"
#include "study/log/log_events.h"
#include "study/schedule/study_plan.h"

namespace fovlab {

namespace vk {
struct DeviceDescription;
}

struct SessionHeaderInputs {
  const StudyPlan* plan = nullptr;
  const vk::DeviceDescription* device = nullptr;
  const ObserverModel* observer = nullptr;  // nullptr: a human at the keys
  std::string presenter;                    // "headless", "window", "fullscreen"
  std::string present_device;               // the device that presents ("" headless)
  std::string frame_path;                   // "on_device", "via_host" (another device presents), "none" (headless)
  std::string gaze;                         // GazeSource::describe()
  nlohmann::json gaze_source;               // gaze_source_json(): its kind, spec and whether --gaze named it
  double refresh_hz = 0.0;                  // measured by the presenter
  std::string started_utc;
  std::map<std::string, std::string> participant_fields;  // the config's [participant] fields
  nlohmann::json image_hashes = nlohmann::json::object();  // StimulusLibrary::image_hashes(): what it showed
};

// The header event; lab_key_id is left null (run_session sets it for a keyed log).
SessionHeaderEvent make_session_header(const SessionHeaderInputs& inputs);

// The header's (and session_resumed's) `gaze_source`: {"kind": tracker|trace|synthetic|mouse,
// "spec": GazeSource::describe(), "requested": whether --gaze named it (false: the default),
// "require": the config's [gaze] require (an empty array: none)}.
nlohmann::json gaze_source_json(GazeSourceKind kind, const std::string& spec, bool requested, const GazeConfig& config);
// The header's `gaze_validation`: {"enabled": false}, or {"enabled": true} with every [validation]
// setting the session runs with (targets, target_offset_deg, target_radius_deg, target_s,
// settle_s, max_accuracy_deg, max_precision_deg, max_attempts, after_breaks).
nlohmann::json gaze_validation_json(const ValidationConfig& validation);

nlohmann::json observer_json(const ObserverModel& model);
ObserverModel observer_from_json(const nlohmann::json& json);  // throws InputError when malformed

// The content hash of every scene file the plan uses, by scene name or path; an image folder's
// is of its entry in `image_hashes` (the plan's image folders -> name -> SHA-256: plan_image_hashes,
// or the images a session loaded).
nlohmann::json scene_hashes(const StudyPlan& plan, const nlohmann::json& image_hashes);

// The header's `stimuli`: every stimulus of the plan by id, its StimulusSpec's JSON with
// is_reference, variant and level.
nlohmann::json stimuli_json(const StudyPlan& plan);

}  // namespace fovlab
