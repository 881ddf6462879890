#include "display/glfw_input.h"

#include <GLFW/glfw3.h>

#include <cstring>

namespace fovlab {

std::string glfw_key_name(int glfw_key, const char* layout_name) {
  const bool printable = (glfw_key >= GLFW_KEY_A && glfw_key <= GLFW_KEY_Z) ||
                         (glfw_key >= GLFW_KEY_0 && glfw_key <= GLFW_KEY_9) ||
                         (glfw_key >= GLFW_KEY_KP_0 && glfw_key <= GLFW_KEY_KP_9);
  if (printable && layout_name && std::strlen(layout_name) == 1) {
    const char c = layout_name[0];
    if (c >= 'a' && c <= 'z') return std::string(1, c);
    if (c >= 'A' && c <= 'Z') return std::string(1, static_cast<char>(c - 'A' + 'a'));
    if (c >= '0' && c <= '9') return std::string(1, c);
  }
  if (glfw_key >= GLFW_KEY_A && glfw_key <= GLFW_KEY_Z)
    return std::string(1, static_cast<char>('a' + (glfw_key - GLFW_KEY_A)));
  if (glfw_key >= GLFW_KEY_0 && glfw_key <= GLFW_KEY_9)
    return std::string(1, static_cast<char>('0' + (glfw_key - GLFW_KEY_0)));
  if (glfw_key >= GLFW_KEY_KP_0 && glfw_key <= GLFW_KEY_KP_9) {
    return std::string(1, static_cast<char>('0' + (glfw_key - GLFW_KEY_KP_0)));
  }
  switch (glfw_key) {
    case GLFW_KEY_SPACE:
      return "space";
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER:
      return "enter";
    case GLFW_KEY_ESCAPE:
      return "escape";
    case GLFW_KEY_LEFT:
      return "left";
    case GLFW_KEY_RIGHT:
      return "right";
    case GLFW_KEY_UP:
      return "up";
    case GLFW_KEY_DOWN:
      return "down";
    default:
      return "";
  }
}

const std::vector<std::pair<int, std::string>>& glfw_gamepad_buttons() {
  static const std::vector<std::pair<int, std::string>> buttons = {
      {GLFW_GAMEPAD_BUTTON_A, "pad_a"},
      {GLFW_GAMEPAD_BUTTON_B, "pad_b"},
      {GLFW_GAMEPAD_BUTTON_X, "pad_x"},
      {GLFW_GAMEPAD_BUTTON_Y, "pad_y"},
      {GLFW_GAMEPAD_BUTTON_DPAD_LEFT, "pad_left"},
      {GLFW_GAMEPAD_BUTTON_DPAD_RIGHT, "pad_right"},
      {GLFW_GAMEPAD_BUTTON_DPAD_UP, "pad_up"},
      {GLFW_GAMEPAD_BUTTON_DPAD_DOWN, "pad_down"},
      {GLFW_GAMEPAD_BUTTON_START, "pad_start"},
      {GLFW_GAMEPAD_BUTTON_BACK, "pad_back"},
      {GLFW_GAMEPAD_BUTTON_LEFT_BUMPER, "pad_lb"},
      {GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER, "pad_rb"},
  };
  return buttons;
}

bool EscapeRepeatDetector::press(double time_s) {
  presses_s_.push_back(time_s);
  while (!presses_s_.empty() && presses_s_.front() < time_s - window_s_) presses_s_.pop_front();
  if (static_cast<int>(presses_s_.size()) < count_) return false;
  presses_s_.clear();
  return true;
}

}  // namespace fovlab
