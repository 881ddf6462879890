#include "foveation/rectangular_mapping.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

double g(double t, double phi) { return phi * t / (phi + t); }
double g_inverse(double s, double phi) { return phi * s / (phi - s); }

}  // namespace

void check_setting_range(const char* field, double value, double low, double high) {
  if (!(value >= low && value <= high))
    throw SettingError(
        field, " " + format_number(value, 6) + ": expected " + format_number(low, 6) + " to " + format_number(high, 6));
}

void check_screen_size(int width_px, int height_px) {
  if (width_px <= 0 || height_px <= 0)
    throw SettingError("screen",
                       " " + std::to_string(width_px) + "x" + std::to_string(height_px) + ": expected a positive size");
}

int reduced_buffer_px(int screen_px, double sigma) { return std::max(1, int(std::lround(screen_px / sigma))); }

double RectangularAxis::to_buffer(double screen_share) const {
  const double c = gaze_share, phi = focal_share;
  const double d = screen_share - c;
  if (d >= 0) return c + (1 - c) * g(d, phi) / g(1 - c, phi);
  return c - c * g(-d, phi) / g(c, phi);
}

double RectangularAxis::to_screen(double buffer_share) const {
  const double c = gaze_share, phi = focal_share;
  if (buffer_share >= c) return c + g_inverse((buffer_share - c) / (1 - c) * g(1 - c, phi), phi);
  return c - g_inverse((c - buffer_share) / c * g(c, phi), phi);
}

double RectangularAxis::density(double screen_share) const {
  const double c = gaze_share, phi = focal_share;
  const double d = screen_share - c;
  const double side = d >= 0 ? 1 - c : c;
  return phi * (phi + side) / ((phi + std::abs(d)) * (phi + std::abs(d)));
}

RectangularAxis rectangular_axis(double gaze_px, double screen_px, double focal_share) {
  const double share = std::isnan(gaze_px) ? 0.5 : gaze_px / screen_px;
  return RectangularAxis{std::clamp(share, kRmfrMinGazeShare, kRmfrMaxGazeShare), focal_share};
}

std::pair<double, double> RectangularMapping::to_buffer_px(double x_px, double y_px) const {
  return {x.to_buffer(x_px / screen_width_px) * buffer_width_px,
          y.to_buffer(y_px / screen_height_px) * buffer_height_px};
}

std::pair<double, double> RectangularMapping::to_screen_px(double u_px, double v_px) const {
  return {x.to_screen(u_px / buffer_width_px) * screen_width_px,
          y.to_screen(v_px / buffer_height_px) * screen_height_px};
}

double RectangularMapping::density(double x_px, double y_px) const {
  return x.density(x_px / screen_width_px) * buffer_width_px / screen_width_px * y.density(y_px / screen_height_px) *
         buffer_height_px / screen_height_px;
}

double RectangularMapping::theoretical_speedup() const {
  return double(screen_width_px) * double(screen_height_px) / (double(buffer_width_px) * double(buffer_height_px));
}

RectangularMapping make_rectangular_mapping(int screen_width_px, int screen_height_px, double sigma,
                                            double focal_share_x, double focal_share_y, double gaze_x_px,
                                            double gaze_y_px) {
  check_screen_size(screen_width_px, screen_height_px);
  check_setting_range("sigma", sigma, kRmfrMinSigma, kRmfrMaxSigma);
  check_setting_range("focal_share_x", focal_share_x, kRmfrMinFocalShare, kRmfrMaxFocalShare);
  check_setting_range("focal_share_y", focal_share_y, kRmfrMinFocalShare, kRmfrMaxFocalShare);
  RectangularMapping mapping;
  mapping.screen_width_px = screen_width_px;
  mapping.screen_height_px = screen_height_px;
  mapping.buffer_width_px = reduced_buffer_px(screen_width_px, sigma);
  mapping.buffer_height_px = reduced_buffer_px(screen_height_px, sigma);
  mapping.x = rectangular_axis(gaze_x_px, screen_width_px, focal_share_x);
  mapping.y = rectangular_axis(gaze_y_px, screen_height_px, focal_share_y);
  return mapping;
}

}  // namespace fovlab
