#include "study/config/input_keys.h"

#include <array>

namespace fovlab {
namespace {
constexpr std::array<const char*, 19> named_inputs = {
    "space", "enter",    "escape",    "left",   "right",    "up",        "down",     "pad_a",  "pad_b", "pad_x",
    "pad_y", "pad_left", "pad_right", "pad_up", "pad_down", "pad_start", "pad_back", "pad_lb", "pad_rb"};
}

bool is_input_name(const std::string& name) {
  if (name.size() == 1 && ((name[0] >= 'a' && name[0] <= 'z') || (name[0] >= '0' && name[0] <= '9'))) return true;
  for (const char* named : named_inputs)
    if (name == named) return true;
  return false;
}

std::string input_names_summary() {
  std::string text = "a..z, 0..9";
  for (const char* named : named_inputs) text += std::string(", ") + named;
  return text;
}

}  // namespace fovlab
