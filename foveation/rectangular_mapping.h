#pragma once
// Rectangular mapping (RMFR, Ye et al. 2022 section 3, eq. 3-7): the screen is shaded in a buffer
// sigma times smaller per axis, each axis warped on its own by the thin-lens curve so that samples
// gather at the gaze. Per axis, in shares of the screen (X = x / W), with the gaze at c and the
// curve's focal length phi = f / W:
//   g(t) = phi t / (phi + t),  g^-1(s) = phi s / (phi - s)
//   screen to buffer, d = X - c:  d >= 0: U = c + (1 - c) g(d) / g(1 - c);  d < 0: U = c - c g(-d) / g(c)
//   buffer to screen:  U >= c: X = c + g^-1((U - c) / (1 - c) g(1 - c));  else X = c - g^-1((c - U) / c g(c))
// Eq. 4 as printed divides the pixel, not the gaze, by W and shows only the positive quadrant; this
// is the form the authors' public shaders use (Bob-Yeah/Rectangular-Mapping-based-Foveated-Rendering, RMFR_Pass1/2.shader). The gaze share is
// clamped to [0.01, 0.99] (at an edge g(0) = 0 would divide by zero), as the authors' code does; a
// gaze that is not a number is taken at the centre. The map fixes 0, c and 1 and is strictly
// increasing, so the buffer covers the whole screen. CPU reference of the GPU passes
// (renderer/foveated_sampling/; docs/foveation.md, "Sampling models").
#include <utility>

namespace fovlab {

inline constexpr double kRmfrMinGazeShare = 0.01;
inline constexpr double kRmfrMaxGazeShare = 0.99;
inline constexpr double kRmfrMinSigma = 1.0;  // the buffer as large as the screen
inline constexpr double kRmfrMaxSigma = 8.0;
inline constexpr double kRmfrMinFocalShare = 1e-3;
inline constexpr double kRmfrMaxFocalShare = 1.0;

// One axis of the map, in shares of the screen and of the buffer ([0, 1] each).
struct RectangularAxis {
  double gaze_share = 0.5;   // c
  double focal_share = 0.3;  // phi

  double to_buffer(double screen_share) const;
  double to_screen(double buffer_share) const;
  // dU/dX: buffer length per screen length at X, phi (phi + 1 - c) / (phi + d)^2 for d = X - c >= 0
  // (c for 1 - c below the gaze); its mean over [0, 1] is 1.
  double density(double screen_share) const;
};

// The axis of a screen `screen_px` pixels long with the gaze at `gaze_px` (clamped, NaN: centre).
RectangularAxis rectangular_axis(double gaze_px, double screen_px, double focal_share);

struct RectangularMapping {
  int screen_width_px = 0, screen_height_px = 0;
  int buffer_width_px = 0, buffer_height_px = 0;  // round(screen / sigma), at least 1
  RectangularAxis x, y;

  // Continuous pixel positions (a pixel's centre at +0.5), screen to buffer and back.
  std::pair<double, double> to_buffer_px(double x_px, double y_px) const;
  std::pair<double, double> to_screen_px(double u_px, double v_px) const;
  // Buffer pixels per screen pixel at a screen position: the sampling density, whose mean over
  // the screen is buffer pixels / screen pixels (1 / sigma^2 up to the rounding of the buffer).
  double density(double x_px, double y_px) const;
  // Screen pixels over buffer pixels: the shading pass's theoretical speed-up (sigma^2 up to rounding).
  double theoretical_speedup() const;
};

// Shared by the reduced-buffer models (RMFR here, KFR in sampling_map.h): SettingError naming
// "screen" unless both sides are positive, or `field` unless low <= value <= high (NaN is outside);
// the buffer's side round(screen_px / sigma), at least 1.
void check_screen_size(int width_px, int height_px);
void check_setting_range(const char* field, double value, double low, double high);
int reduced_buffer_px(int screen_px, double sigma);

// SettingError naming "sigma" (kRmfrMinSigma to kRmfrMaxSigma), "focal_share_x" / "focal_share_y"
// (kRmfrMinFocalShare to kRmfrMaxFocalShare: f as a share of the screen's width / height) or the
// screen size (positive).
RectangularMapping make_rectangular_mapping(int screen_width_px, int screen_height_px, double sigma,
                                            double focal_share_x, double focal_share_y, double gaze_x_px,
                                            double gaze_y_px);

}  // namespace fovlab
