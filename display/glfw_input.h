#pragma once
// GLFW input to the normalised names of presenter.h, separate from the window so tests can check
// the mapping without a display.
#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace fovlab {

// The normalised name of a GLFW key (GLFW_KEY_*), or "" for keys a study never binds. Letters and
// digits follow the keyboard layout: `layout_name` is what glfwGetKeyName returned for the key
// (may be null); a single a-z/0-9 character from it wins, so the key labelled Z on a German
// keyboard is "z". Otherwise GLFW's US-position name is used. Keypad digits and keypad Enter map
// to the digits and "enter".
std::string glfw_key_name(int glfw_key, const char* layout_name);

// GLFW's standard gamepad buttons (GLFW_GAMEPAD_BUTTON_*) a study can bind, with their names.
const std::vector<std::pair<int, std::string>>& glfw_gamepad_buttons();

// Escape pressed `count` times within `window_s` seconds: the operator's way to stop a session.
class EscapeRepeatDetector {
 public:
  explicit EscapeRepeatDetector(int count = 3, double window_s = 1.0) : count_(count), window_s_(window_s) {}
  // Records one press at time_s (non-decreasing); true when it completes a repeat.
  bool press(double time_s);

 private:
  int count_;
  double window_s_;
  std::deque<double> presses_s_;
};

}  // namespace fovlab
