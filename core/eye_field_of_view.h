#pragma once
// An eye's asymmetric field of view, the one type the headset's config (study/), its image plane
// (foveation/display_geometry.h) and the renderer's eye view (renderer/scene/eye_view.h) share. As
// OpenXR's XrFovf gives it: the angles in radians from the eye's forward axis to the left, right,
// upper and lower edges of its image (left and down are negative when the axis lies inside the
// image, as in a headset). A config writes them in degrees ([display] left_eye_fov_deg).
#include <cmath>
#include <numbers>

namespace fovlab {

struct EyeFieldOfView {
  double angle_left_rad = 0.0;
  double angle_right_rad = 0.0;
  double angle_up_rad = 0.0;
  double angle_down_rad = 0.0;
  bool operator==(const EyeFieldOfView&) const = default;
};

inline EyeFieldOfView field_of_view_from_deg(double left_deg, double right_deg, double up_deg, double down_deg) {
  constexpr double radians_per_degree = std::numbers::pi / 180.0;
  return {left_deg * radians_per_degree, right_deg * radians_per_degree, up_deg * radians_per_degree,
          down_deg * radians_per_degree};
}

// An eye's image plane is placed this far from it where a distance is needed (a DisplayGeometry in
// millimetres); only the angles matter, so it is a convention.
inline constexpr double kFieldOfViewPlaneDistanceMm = 1000.0;

}  // namespace fovlab
