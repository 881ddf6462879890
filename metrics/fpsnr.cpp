#include "metrics/fpsnr.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "metrics/image_checks.h"

// FPSNR of Lee, Pattichis, Bovik, "Foveated video quality assessment", IEEE Trans. Multimedia 4(1),
// 2002 (Ye et al. 2022, ref. [14]): the foveated MSE weights each squared error by the square of the
// normalised local bandwidth f_n(x) = f_m(x) / f_m(fovea), i.e. by the local sampling density of
// the foveated (curvilinear) image, and FPSNR = 10 log10(peak^2 / FMSE). The local bandwidth is the
// smaller of the eye's cutoff frequency at the pixel's eccentricity (Geisler & Perry 1998, the
// model Lee et al. use) and the display's Nyquist frequency.

namespace fovlab::metrics {
namespace {

using detail::colour_channel_count;
using detail::require_same_size;
using detail::require_valid_layout;
using detail::size_text;

// Foveation model of Geisler & Perry (Proc. SPIE 3299, 1998), adopted by Lee et al. 2002: contrast
// threshold CT(f, e) = CT0 exp(alpha f (e + e2) / e2); the cutoff frequency is where CT reaches 1.
constexpr double kCt0 = 1.0 / 64.0;  // minimal contrast threshold
constexpr double kAlpha = 0.106;     // spatial frequency decay constant
constexpr double kE2 = 2.3;          // half-resolution eccentricity, degrees

constexpr double kPeak = 1.0;  // values in [0, 1], as psnr()

// f_c(e) = e2 ln(1 / CT0) / (alpha (e + e2)), cycles per degree.
double cutoff_frequency(double eccentricity_deg) {
  return kE2 * std::log(1.0 / kCt0) / (kAlpha * (eccentricity_deg + kE2));
}

void require_valid_display(const DisplayGeometry& d) {
  const bool sizes_ok = std::isfinite(d.width_mm) && d.width_mm > 0.0 && std::isfinite(d.height_mm) &&
                        d.height_mm > 0.0 && std::isfinite(d.viewing_distance_mm) && d.viewing_distance_mm > 0.0;
  if (d.width_px <= 0 || d.height_px <= 0 || !sizes_ok) {
    throw std::invalid_argument("FPSNR: display sizes must be positive and finite");
  }
}

// w(x) = (f_m(x) / f_m(gaze))^2 with f_m = min(f_c(e), f_d), in double.
class FoveationWeight {
 public:
  FoveationWeight(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px)
      : display_(display), gaze_x_(gaze_x_px), gaze_y_(gaze_y_px) {
    require_valid_display(display);
    if (!std::isfinite(gaze_x_px) || !std::isfinite(gaze_y_px)) {
      throw std::invalid_argument("FPSNR: the gaze point must be finite");
    }
    // Display Nyquist frequency: half the pixels per degree at the display's centre, one value for
    // the whole image (our reading of Lee et al.'s display term; docs/analysis.md, "FPSNR").
    nyquist_ = 0.5 * display.pixels_per_degree_at_centre();
    foveal_ = std::min(cutoff_frequency(0.0), nyquist_);
  }
  double at(int x, int y) const {
    const double e = eccentricity_deg(display_, gaze_x_, gaze_y_, x + 0.5, y + 0.5);
    const double normalised = std::min(cutoff_frequency(e), nyquist_) / foveal_;
    return normalised * normalised;
  }

 private:
  DisplayGeometry display_;
  double gaze_x_, gaze_y_;
  double nyquist_ = 0.0, foveal_ = 0.0;
};

}  // namespace

Image foveation_weights(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px) {
  const FoveationWeight weight(display, gaze_x_px, gaze_y_px);
  Image weights(display.width_px, display.height_px, 1);
  for (int y = 0; y < display.height_px; ++y)
    for (int x = 0; x < display.width_px; ++x) weights.at(x, y, 0) = static_cast<float>(weight.at(x, y));
  return weights;
}

FpsnrResult fpsnr(const Image& a, const Image& b, const DisplayGeometry& display, double gaze_x_px, double gaze_y_px) {
  require_valid_layout(a);
  require_valid_layout(b);
  require_valid_display(display);
  require_same_size(a, b);
  if (a.width != display.width_px || a.height != display.height_px) {
    throw std::invalid_argument("FPSNR: images are " + size_text(a) + " but the display has " +
                                std::to_string(display.width_px) + "x" + std::to_string(display.height_px) +
                                " pixels; the image must fill the display");
  }
  const int channels = colour_channel_count(a);
  if (channels != colour_channel_count(b)) {
    throw std::invalid_argument("images differ in colour channels: " + std::to_string(a.channels) + " vs " +
                                std::to_string(b.channels));
  }
  const FoveationWeight weight(display, gaze_x_px, gaze_y_px);  // in double, unlike foveation_weights()
  const auto stride_a = static_cast<std::size_t>(a.channels);
  const auto stride_b = static_cast<std::size_t>(b.channels);
  double weighted_error = 0.0;
  double weight_sum = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      const double w = weight.at(x, y);
      const std::size_t i =
          static_cast<std::size_t>(y) * static_cast<std::size_t>(a.width) + static_cast<std::size_t>(x);
      double squared = 0.0;
      for (int c = 0; c < channels; ++c) {
        const double d = static_cast<double>(a.pixels[i * stride_a + static_cast<std::size_t>(c)]) -
                         static_cast<double>(b.pixels[i * stride_b + static_cast<std::size_t>(c)]);
        squared += d * d;
      }
      weighted_error += w * squared;
      weight_sum += w;
    }
  }
  FpsnrResult result;
  result.fmse = weighted_error / (weight_sum * channels);
  result.identical = result.fmse == 0.0;
  result.fpsnr_db =
      result.identical ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(kPeak * kPeak / result.fmse);
  return result;
}

}  // namespace fovlab::metrics
