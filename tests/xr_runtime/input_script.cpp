// The test runtime's input devices: the interaction profiles it knows (the allowlists bindings are
// checked against) and the scripted controller and eye tracker of a session, read from the
// environment when the session is created:
//   FOVLAB_TEST_XR_CONTROLLER = xbox (default) | vive | simple: the connected controller's profile;
//   FOVLAB_TEST_XR_INPUT = a file of lines "<frame> <input path>": that button is pressed during the
//     session's frame-th xrWaitFrame and released after it (blank lines and lines starting with '#'
//     are skipped);
//   FOVLAB_TEST_XR_PRESS_QUEUE = a file the test appends lines "<input path>" to while the session
//     runs: at each xrSyncActions the lines appended since the last are taken, each pressed during
//     the next xrWaitFrame's frame and released after it (a line not yet ended by a newline waits for
//     a later sync), so a test can answer what the application shows it, as a participant would;
//   FOVLAB_TEST_XR_GAZE = "yaw_deg,pitch_deg": the eye gaze ray from the head (default "0,0");
//   FOVLAB_TEST_XR_GAZE_AWAY = "first,last,yaw_deg,pitch_deg": the gaze located at the predicted
//     display time of frames first..last (xrWaitFrame counts) is that ray instead;
//   FOVLAB_TEST_XR_GAZE_LOST = "first,last": the gaze of those frames has no location (not tracked);
//   FOVLAB_TEST_XR_HEAD = "yaw_deg_per_s,x_m_per_s": the head turning right and moving along LOCAL's
//     x at constant rates on the virtual clock (default "0,0", still).
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "tests/xr_runtime/test_runtime.h"

namespace fovlab::test_xr {
namespace {

constexpr std::array<std::string_view, 2> kHands{"/user/hand/left", "/user/hand/right"};
constexpr std::array<std::string_view, 1> kGamepad{"/user/gamepad"};
constexpr std::array<std::string_view, 1> kEyes{"/user/eyes_ext"};

// The allowlists of the OpenXR 1.0 specification for the profiles fovlab suggests bindings for.
constexpr std::array<std::string_view, 5> kSimpleControllerComponents{
    "/input/select/click", "/input/menu/click", "/input/grip/pose", "/input/aim/pose", "/output/haptic"};
constexpr std::array<std::string_view, 12> kViveControllerComponents{
    "/input/system/click",   "/input/squeeze/click", "/input/menu/click", "/input/trigger/click",
    "/input/trigger/value",  "/input/trackpad/x",    "/input/trackpad/y", "/input/trackpad/click",
    "/input/trackpad/touch", "/input/grip/pose",     "/input/aim/pose",   "/output/haptic"};
constexpr std::array<std::string_view, 24> kXboxControllerComponents{"/input/menu/click",
                                                                     "/input/view/click",
                                                                     "/input/a/click",
                                                                     "/input/b/click",
                                                                     "/input/x/click",
                                                                     "/input/y/click",
                                                                     "/input/dpad_down/click",
                                                                     "/input/dpad_right/click",
                                                                     "/input/dpad_up/click",
                                                                     "/input/dpad_left/click",
                                                                     "/input/shoulder_left/click",
                                                                     "/input/shoulder_right/click",
                                                                     "/input/thumbstick_left/click",
                                                                     "/input/thumbstick_right/click",
                                                                     "/input/trigger_left/value",
                                                                     "/input/trigger_right/value",
                                                                     "/input/thumbstick_left/x",
                                                                     "/input/thumbstick_left/y",
                                                                     "/input/thumbstick_right/x",
                                                                     "/input/thumbstick_right/y",
                                                                     "/output/haptic_left",
                                                                     "/output/haptic_right",
                                                                     "/output/haptic_left_trigger",
                                                                     "/output/haptic_right_trigger"};
constexpr std::array<std::string_view, 1> kEyeGazeComponents{"/input/gaze_ext/pose"};

const std::array<InteractionProfile, 4>& interaction_profiles() {
  static const std::array<InteractionProfile, 4> profiles{{
      {"/interaction_profiles/khr/simple_controller", kHands, kSimpleControllerComponents, ""},
      {"/interaction_profiles/htc/vive_controller", kHands, kViveControllerComponents, ""},
      {"/interaction_profiles/microsoft/xbox_controller", kGamepad, kXboxControllerComponents, ""},
      {"/interaction_profiles/ext/eye_gaze_interaction", kEyes, kEyeGazeComponents,
       XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME},
  }};
  return profiles;
}

void log_malformed(const std::string& what) {
  std::fprintf(stderr, "fovlab test runtime: %s\n", what.c_str());
  std::fflush(stderr);
}

bool read_controller(SimulatedController& controller) {
  const char* setting = std::getenv("FOVLAB_TEST_XR_CONTROLLER");
  const std::string_view name = setting == nullptr ? "" : setting;
  if (name.empty() || name == "xbox") {
    controller = SimulatedController::xbox;
  } else if (name == "vive") {
    controller = SimulatedController::vive;
  } else if (name == "simple") {
    controller = SimulatedController::simple;
  } else {
    log_malformed("FOVLAB_TEST_XR_CONTROLLER=" + std::string(name) + ": expected xbox, vive or simple");
    return false;
  }
  return true;
}

// A button of the connected controller, or false with `where` and the reason on stderr.
bool is_pressable(const SimulatedInput& input, const std::string& where, const std::string& path) {
  if (is_controller_button(input.controller, path)) return true;
  log_malformed(where + path + " is not a button of " + std::string(controller_profile(input.controller)));
  return false;
}

bool read_presses(SimulatedInput& input) {
  const char* setting = std::getenv("FOVLAB_TEST_XR_INPUT");
  if (setting == nullptr || *setting == '\0') return true;
  std::ifstream file(setting);
  if (!file) {
    log_malformed(std::string("FOVLAB_TEST_XR_INPUT: cannot read ") + setting);
    return false;
  }
  std::string line;
  for (int line_number = 1; std::getline(file, line); ++line_number) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    std::istringstream fields(line);
    ScriptedPress press;
    std::string extra;
    const bool parsed = static_cast<bool>(fields >> press.frame >> press.input) && !(fields >> extra);
    const std::string where = std::string(setting) + ":" + std::to_string(line_number) + ": ";
    if (!parsed || press.frame < 1) {
      log_malformed(where + "expected \"<frame> <input path>\" with a frame of 1 or more, got \"" + line + "\"");
      return false;
    }
    if (!is_pressable(input, where, press.input)) return false;
    input.presses.push_back(press);
  }
  return true;
}

bool read_gaze(SimulatedInput& input) {
  const char* setting = std::getenv("FOVLAB_TEST_XR_GAZE");
  if (setting == nullptr || *setting == '\0') return true;
  char* end = nullptr;
  const double yaw = std::strtod(setting, &end);
  const bool has_comma = end != setting && *end == ',';
  const char* pitch_text = has_comma ? end + 1 : end;
  const double pitch = std::strtod(pitch_text, &end);
  if (!has_comma || end == pitch_text || *end != '\0' || !std::isfinite(yaw) || !std::isfinite(pitch) ||
      std::fabs(yaw) > 90.0 || std::fabs(pitch) > 90.0) {
    log_malformed(std::string("FOVLAB_TEST_XR_GAZE=") + setting +
                  ": expected \"yaw_deg,pitch_deg\", each between -90 and 90");
    return false;
  }
  input.gaze_yaw_deg = yaw;
  input.gaze_pitch_deg = pitch;
  return true;
}

// `count` comma-separated numbers of the environment variable `name` (false, logged, when malformed).
bool read_numbers(const char* name, size_t count, std::vector<double>& numbers) {
  const char* setting = std::getenv(name);
  if (setting == nullptr || *setting == '\0') return true;
  numbers.clear();
  const char* at = setting;
  for (size_t i = 0; i < count; ++i) {
    char* end = nullptr;
    const double number = std::strtod(at, &end);
    const bool separated = i + 1 < count ? *end == ',' : *end == '\0';
    if (end == at || !separated || !std::isfinite(number)) {
      numbers.clear();
      return false;
    }
    numbers.push_back(number);
    at = end + 1;
  }
  return true;
}

bool read_gaze_script(SimulatedInput& input) {
  std::vector<double> away, lost;
  const auto frames_ok = [](const std::vector<double>& values) {
    return values[0] >= 1 && values[1] >= values[0] && values[0] == std::floor(values[0]) &&
           values[1] == std::floor(values[1]);
  };
  if (!read_numbers("FOVLAB_TEST_XR_GAZE_AWAY", 4, away) ||
      (!away.empty() && (!frames_ok(away) || std::fabs(away[2]) > 90.0 || std::fabs(away[3]) > 90.0))) {
    log_malformed(std::string("FOVLAB_TEST_XR_GAZE_AWAY=") + std::getenv("FOVLAB_TEST_XR_GAZE_AWAY") +
                  ": expected \"first,last,yaw_deg,pitch_deg\", frames 1 <= first <= last, angles between -90 and 90");
    return false;
  }
  if (!read_numbers("FOVLAB_TEST_XR_GAZE_LOST", 2, lost) || (!lost.empty() && !frames_ok(lost))) {
    log_malformed(std::string("FOVLAB_TEST_XR_GAZE_LOST=") + std::getenv("FOVLAB_TEST_XR_GAZE_LOST") +
                  ": expected \"first,last\", frames 1 <= first <= last");
    return false;
  }
  if (!away.empty()) {
    input.gaze_away_first_frame = static_cast<int64_t>(away[0]);
    input.gaze_away_last_frame = static_cast<int64_t>(away[1]);
    input.gaze_away_yaw_deg = away[2];
    input.gaze_away_pitch_deg = away[3];
  }
  if (!lost.empty()) {
    input.gaze_lost_first_frame = static_cast<int64_t>(lost[0]);
    input.gaze_lost_last_frame = static_cast<int64_t>(lost[1]);
  }
  return true;
}

bool read_head(SimulatedInput& input) {
  const char* setting = std::getenv("FOVLAB_TEST_XR_HEAD");
  if (setting == nullptr || *setting == '\0') return true;
  char* end = nullptr;
  const double yaw_rate = std::strtod(setting, &end);
  const bool has_comma = end != setting && *end == ',';
  const char* x_text = has_comma ? end + 1 : end;
  const double x_rate = std::strtod(x_text, &end);
  if (!has_comma || end == x_text || *end != '\0' || !std::isfinite(yaw_rate) || !std::isfinite(x_rate) ||
      std::fabs(yaw_rate) > 360.0 || std::fabs(x_rate) > 10.0) {
    log_malformed(std::string("FOVLAB_TEST_XR_HEAD=") + setting +
                  ": expected \"yaw_deg_per_s,x_m_per_s\", at most 360 and 10 in size");
    return false;
  }
  input.head_yaw_deg_per_s = yaw_rate;
  input.head_x_m_per_s = x_rate;
  return true;
}

}  // namespace

const InteractionProfile* find_interaction_profile(std::string_view path) {
  for (const InteractionProfile& profile : interaction_profiles()) {
    if (profile.path == path) return &profile;
  }
  return nullptr;
}

bool profile_has_binding(const InteractionProfile& profile, std::string_view binding) {
  for (const std::string_view user_path : profile.user_paths) {
    if (!binding.starts_with(user_path)) continue;
    const std::string_view subpath = binding.substr(user_path.size());
    for (const std::string_view component : profile.components) {
      if (component == subpath) return true;
      // An identifier without its component: "/input/trigger" of "/input/trigger/click".
      if (subpath.size() > 1 && component.starts_with(subpath) && component[subpath.size()] == '/') return true;
    }
  }
  return false;
}

std::string_view controller_profile(SimulatedController controller) {
  switch (controller) {
    case SimulatedController::vive:
      return "/interaction_profiles/htc/vive_controller";
    case SimulatedController::simple:
      return "/interaction_profiles/khr/simple_controller";
    case SimulatedController::xbox:
      break;
  }
  return "/interaction_profiles/microsoft/xbox_controller";
}

bool is_controller_button(SimulatedController controller, std::string_view input) {
  const InteractionProfile* profile = find_interaction_profile(controller_profile(controller));
  return profile != nullptr && input.ends_with("/click") && input.find("/input/") != std::string_view::npos &&
         profile_has_binding(*profile, input);
}

bool read_simulated_input(SimulatedInput& input) {
  if (const char* queue = std::getenv("FOVLAB_TEST_XR_PRESS_QUEUE")) input.press_queue = queue;
  return read_controller(input.controller) && read_presses(input) && read_gaze(input) && read_gaze_script(input) &&
         read_head(input);
}

bool take_queued_presses(SimulatedInput& input, int64_t next_frame) {
  if (input.press_queue.empty()) return true;
  std::ifstream file(input.press_queue, std::ios::binary);
  if (!file) return true;  // nothing queued yet
  file.seekg(static_cast<std::streamoff>(input.press_queue_read));
  std::string line;
  // getline sets eof only on a line that the end of the file cut short: one still being written.
  while (std::getline(file, line) && !file.eof()) {
    input.press_queue_read += static_cast<int64_t>(line.size()) + 1;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string path = line.substr(first, line.find_last_not_of(" \t\r") + 1 - first);
    if (!is_pressable(input, input.press_queue + ": ", path)) return false;
    input.presses.push_back({next_frame, path});
  }
  return true;
}

}  // namespace fovlab::test_xr
