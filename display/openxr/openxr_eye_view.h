#pragma once
// The renderer's eye view (renderer/scene/eye_view.h) from a view the runtime located in the
// session's VIEW space, i.e. relative to the head: the head-locked view model, where the scene's
// camera path is the head and each eye sits where the headset says it sits in the head, looking
// through its own asymmetric field of view. OpenXR's VIEW space has x right, y up and z backwards,
// as the eye view's head frame; its lengths are metres, the scene's are its own units.
#include <openxr/openxr.h>

#include "renderer/scene/eye_view.h"

namespace fovlab {

// The pose's position times scene_units_per_metre, its orientation as it is, the four angles of
// its XrFovf as they are (radians).
EyeView eye_view_from_openxr(const XrView& view_in_head, double scene_units_per_metre = 1.0);

}  // namespace fovlab
