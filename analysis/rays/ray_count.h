#pragma once
// Ray-reduction analysis of a three-zone foveated frame (Polychronakis et al. 2021, section 5.1 and Table 1): the
// foveal zone is traced at full resolution (one ray a pixel), the middle zone at 1/4 (one ray per
// 4 pixels), the outer zone at 1/16. A zone "of angle A degrees" holds the pixels whose centre has an
// eccentricity of at most A / 2 (the angle is the zone's full aperture, its diameter); this is the
// convention that reproduces Table 1 (docs/analysis.md, "Ray reduction").
#include <cstdint>
#include <vector>

#include "foveation/display_geometry.h"

namespace fovlab::analysis {

struct RayCell {
  double foveal_deg = 0.0;
  double middle_deg = 0.0;
  int64_t foveal_pixels = 0;  // eccentricity <= foveal_deg / 2
  int64_t middle_pixels = 0;  // foveal_deg / 2 < eccentricity <= middle_deg / 2
  int64_t outer_pixels = 0;   // the rest of the frame
  double rays = 0.0;          // foveal + middle / 4 + outer / 16
  double speedup = 0.0;       // width * height / rays
};

// Every pixel's eccentricity from the gaze point, sorted, so each cell costs two binary searches.
class EccentricityTable {
 public:
  EccentricityTable(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px);
  int64_t pixels_within(double eccentricity_deg) const;  // pixels with eccentricity <= the bound
  int64_t pixel_count() const { return static_cast<int64_t>(sorted_eccentricity_deg_.size()); }

 private:
  std::vector<double> sorted_eccentricity_deg_;
};

// One cell. A middle angle smaller than the foveal one gives an empty middle zone. Throws
// InputError for negative or non-finite angles.
RayCell count_rays(const EccentricityTable& table, double foveal_deg, double middle_deg);

// Every (foveal, middle) combination, foveal-major.
std::vector<RayCell> count_ray_grid(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                                    const std::vector<double>& foveal_deg, const std::vector<double>& middle_deg);

}  // namespace fovlab::analysis
