#pragma once
// The built-in stand-in for Polychronakis et al. 2021's scene (Sponza with three glass Stanford dragons of different
// colours): an arcaded courtyard open to the sky, lit by a distant sun-like emissive quad and two
// lamps under the galleries, with three tinted glass objects on pedestals. docs/path-tracing.md.
#include "renderer/path_tracing/path_scene.h"

namespace fovlab {

// Units are metres, y is up. The camera walks along the courtyard from 0 to 12 s.
PathScene courtyard_scene();

}  // namespace fovlab
