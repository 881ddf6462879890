#include "foveation/acuity_model.h"

#include <cmath>

namespace fovlab {

double acuity_fit(double eccentricity_deg) {
  constexpr double amplitude = 0.90964, scale_deg = 2.9661, floor = 0.00792;  // Polychronakis et al. 2021, eq. 1
  return amplitude * std::exp(-eccentricity_deg / scale_deg) + floor;
}

double AcuityModel::trace_probability(double eccentricity_deg) const {
  if (!(eccentricity_deg > fovea_radius_deg)) return 1.0;  // also NaN and negative values
  if (eccentricity_deg > outer_periphery_radius_deg) return 0.0;
  return acuity_fit(eccentricity_deg);
}

}  // namespace fovlab
