#pragma once
// The acuity model of Polychronakis et al. 2021 (section 3.2, eq. 1-2), shared by FIPR's foveation mask and the
// path-tracer emulation's zones: an exponential fit to Mandelbaum & Sloan's (1947) acuity against
// eccentricity, turned into the probability that a pixel is traced at full resolution.
//
//   V(w) = 0.90964 exp(-w / 2.9661) + 0.00792                           (eq. 1, w in degrees)
//   P(w) = 1 for w <= fovea, V(w) for fovea < w <= outer periphery, 0 beyond    (eq. 2 + zones)
//
// Polychronakis et al. 2023 prints eq. 1 with a positive exponent; that grows without bound (V(1) = 1.28 already)
// and cannot be a probability nor a fall-off, which its text calls it: the negative exponent of
// Polychronakis et al. 2021 is the fit. Definitions and plots: docs/foveation.md ("Acuity model").
#include <limits>

namespace fovlab {

// Eq. 1: relative acuity at an eccentricity (degrees, >= 0); 0.91756 at 0, tending to 0.00792.
double acuity_fit(double eccentricity_deg);

struct AcuityModel {
  double fovea_radius_deg =
      7.5;  // eccentricity (a radius, not an aperture) up to which P = 1; FIPR's default (study/stimulus/render_method.cpp)
  double outer_periphery_radius_deg = std::numeric_limits<double>::infinity();  // beyond it P = 0

  // Eq. 2 with the outer periphery: in [0, 1]. A non-finite or negative eccentricity (a gaze sample
  // that is not a number) is treated as the fovea: the pixel is traced in full, never dropped.
  double trace_probability(double eccentricity_deg) const;
};

}  // namespace fovlab
