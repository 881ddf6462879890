#include "bench/frame_errors.h"

#include "metrics/flip.h"
#include "metrics/fpsnr.h"
#include "metrics/image_metrics.h"

namespace fovlab::bench {

FrameErrors frame_errors(const Image& gt, const Image& test, const DisplayGeometry& display, double gaze_x_px,
                         double gaze_y_px, double flip_pixels_per_degree) {
  FrameErrors errors;
  errors.ssim = metrics::ssim(gt, test).mean_ssim;
  const metrics::PsnrResult psnr = metrics::psnr(gt, test);
  if (!psnr.identical) errors.psnr_db = psnr.psnr_db;
  errors.flip = metrics::flip(gt, test, flip_pixels_per_degree).mean_flip;
  const metrics::FpsnrResult fpsnr = metrics::fpsnr(gt, test, display, gaze_x_px, gaze_y_px);
  if (!fpsnr.identical) errors.fpsnr_db = fpsnr.fpsnr_db;
  return errors;
}

FrameErrors frame_errors(const Image& gt, const Image& test, const DisplayGeometry& display, double gaze_x_px,
                         double gaze_y_px) {
  return frame_errors(gt, test, display, gaze_x_px, gaze_y_px, display.pixels_per_degree_at_centre());
}

}  // namespace fovlab::bench
