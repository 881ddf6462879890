#pragma once
// The normalised key and gamepad-button names a config may bind to answers (the names the
// presenters deliver; display/presenter.h).
#include <string>

namespace fovlab {

bool is_input_name(const std::string& name);
std::string input_names_summary();  // for messages: "a..z, 0..9, space, enter, ..."

}  // namespace fovlab
