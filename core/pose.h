#pragma once
// A rigid pose: a position in metres and an orientation as a unit quaternion (x, y, z, w), in
// whatever space its user names (a head relative to its start, an eye in a headset's LOCAL space).
#include <array>

namespace fovlab {

struct Pose {
  std::array<double, 3> position_m{0.0, 0.0, 0.0};
  std::array<double, 4> orientation{0.0, 0.0, 0.0, 1.0};  // unit quaternion x, y, z, w
  bool operator==(const Pose&) const = default;
};

}  // namespace fovlab
