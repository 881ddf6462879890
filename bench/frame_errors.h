#pragma once
// The error of a display image (sRGB-encoded) against a reference's, as fovlab bench measures each
// cell against its GT frame (and fovlab resample a frame against the one it was sampled from): SSIM
// over the whole frame, PSNR, LDR-FLIP at the display's pixels per degree, FPSNR at the gaze.
#include <optional>

#include "core/image.h"
#include "foveation/display_geometry.h"

namespace fovlab::bench {

struct FrameErrors {
  double ssim = 1.0;
  std::optional<double> psnr_db;  // none when identical
  double flip = 0.0;
  std::optional<double> fpsnr_db;  // none when identical
};

// FLIP at `flip_pixels_per_degree`.
FrameErrors frame_errors(const Image& gt, const Image& test, const DisplayGeometry& display, double gaze_x_px,
                         double gaze_y_px, double flip_pixels_per_degree);
// FLIP at the display's pixels per degree at its centre.
FrameErrors frame_errors(const Image& gt, const Image& test, const DisplayGeometry& display, double gaze_x_px,
                         double gaze_y_px);

}  // namespace fovlab::bench
