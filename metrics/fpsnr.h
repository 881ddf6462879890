#pragma once
// FPSNR, the foveated peak signal-to-noise ratio that Ye et al. 2022 (section 5.1/5.3.2, its refs. [14]
// and [29]) reports: a PSNR whose squared errors are weighted per pixel by how much detail the eye
// resolves there. Definition of S. Lee, M. S. Pattichis, A. C. Bovik, "Foveated video quality
// assessment", IEEE Transactions on Multimedia 4(1):129-132, 2002 (Ye et al. 2022's [14]), with the
// foveation model of W. S. Geisler, J. S. Perry, "A real-time foveated multiresolution system for
// low-bandwidth video communication", Proc. SPIE 3299, 1998. Full definition: docs/analysis.md,
// section "FPSNR".
//
//   e(x)    eccentricity of pixel x's centre from the gaze point, degrees (display_geometry.h)
//   fc(e)   = e2 ln(1 / CT0) / (alpha (e + e2))    cutoff frequency, cycles/degree;
//             CT0 = 1/64, alpha = 0.106, e2 = 2.3 degrees (Geisler & Perry 1998)
//   fd      = pixels_per_degree_at_centre / 2      display Nyquist frequency, cycles/degree
//   fm(x)   = min(fc(e(x)), fd)                    local bandwidth
//   w(x)    = (fm(x) / fm(gaze))^2                 weight in (0, 1]; 1 where the display limits
//   FMSE    = sum_x w(x) sum_c (a - b)^2 / (C sum_x w(x))     over the C colour channels
//   FPSNR   = 10 log10(1 / FMSE) dB                peak value 1
//
// Inputs: sRGB-encoded values in [0, 1] compared as stored (as psnr()), the image covering the
// whole display pixel for pixel.
#include "core/image.h"
#include "foveation/display_geometry.h"

namespace fovlab::metrics {

struct FpsnrResult {
  double fmse = 0.0;       // foveation-weighted mean squared error over the colour samples
  double fpsnr_db = 0.0;   // 10 log10(1 / fmse); +infinity when identical
  bool identical = false;  // fmse == 0: every colour sample is equal (all weights are positive)
};

// Foveation weights w(x) of every pixel of `display` for a gaze at (gaze_x_px, gaze_y_px) (pixel
// coordinates of display_geometry.h: pixel (x, y) has its centre at (x + 0.5, y + 0.5); the gaze
// may lie anywhere on the display's plane). One channel, display.width_px x display.height_px.
// Throws std::invalid_argument for a gaze that is not finite or a display whose sizes are not
// positive and finite.
Image foveation_weights(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px);

// FPSNR of `b` against `a` seen on `display` with the gaze at (gaze_x_px, gaze_y_px). Channels as
// psnr(): R, G, B (alpha ignored) or the one grey channel; RGB may be compared with RGBA, grey with
// colour may not. Both images must be display.width_px x display.height_px. Throws
// std::invalid_argument otherwise, and for the cases of foveation_weights().
FpsnrResult fpsnr(const Image& a, const Image& b, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px);

}  // namespace fovlab::metrics
