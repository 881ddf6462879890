#pragma once
// The three zones of the emulated foveated path tracer (Polychronakis et al. 2021 sections 3.2 and 4): which of the
// full-resolution (foveal), 1/4 (middle) and 1/16 (outer) buffers a pixel shows for a gaze sample,
// with linear bands between zones. CPU code: the reference for renderer/zone_blend/zone_blender.h,
// the zone pictures of `fovlab blend --zones-out`, and the zone-buffer decimation. Definitions in
// docs/foveated-path-tracing.md ("Zones and blend").
//
// Angles are full apertures, as in `fovlab rays` (analysis/rays/ray_count.h, the reading that
// reproduces Polychronakis et al. 2021 Table 1): a foveal zone of F degrees holds the pixels whose eccentricity is at
// most F / 2. A band of B degrees (of eccentricity) centred on each boundary ramps linearly from the
// inner zone to the outer one; B = 0 is a hard edge (a pixel exactly on a boundary is inner).
#include "core/image.h"
#include "foveation/display_geometry.h"

namespace fovlab {

// Polychronakis et al. 2021 pairs each foveal level with a middle level 52.5 degrees wider (5 -> 57.5 ... 30 ->
// 82.5, section 4.4); fovlab's default middle boundary. Eq. 2 alone cannot set it: beyond the fovea
// P(w) = V(w) does not depend on the foveal angle (docs/foveated-path-tracing.md).
inline constexpr double kMiddleOverFovealDeg = 52.5;

double default_middle_deg(double foveal_deg);

struct ZoneBounds {
  double foveal_deg = 10.0;  // full aperture
  double middle_deg = 62.5;  // full aperture; <= foveal_deg: no middle zone
  double band_deg = 1.0;     // width of each linear band, degrees of eccentricity
};

// Throws InputError naming the value when an angle is negative or non-finite.
void check_zone_bounds(const ZoneBounds& bounds);

struct ZoneWeights {
  double foveal = 0.0;
  double middle = 0.0;
  double outer = 0.0;  // the three sum to 1
};

// The weights of the three buffers at an eccentricity (degrees). A non-finite eccentricity is
// treated as the gaze point (all foveal), as the acuity model does.
ZoneWeights zone_weights(const ZoneBounds& bounds, double eccentricity_deg);

// The three buffers, all at full size (the middle and outer ones already upsampled), blended for a
// gaze point in pixel coordinates (it may lie off the screen), in double: the GPU blend's
// reference. Same size and channel count for all three; InputError otherwise.
Image blend_zones_reference(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px,
                            const ZoneBounds& bounds, const Image& foveal, const Image& middle, const Image& outer);

// A picture of the zones: red foveal, green middle, blue outer, mixed by the weights (sRGB-encoded
// RGB, 1 = full), for the display's pixel size.
Image zone_map(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px, const ZoneBounds& bounds);

// Nearest-neighbour decimation by `factor` per axis (Polychronakis et al. 2021: the zone buffers "drop extra
// pixels"): output pixel (i, j) is input pixel (i * factor + factor / 2, j * factor + factor / 2),
// the one whose area holds the output pixel's centre (the lower-right one of a tie), clamped to the
// last row and column. Output size: ceil(input / factor) per axis.
Image decimate_nearest(const Image& image, int factor);

}  // namespace fovlab
