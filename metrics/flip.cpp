#include "metrics/flip.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/number_text.h"
#include "metrics/image_checks.h"

// LDR-FLIP (Andersson et al. 2020). Paper sections cited below refer to "FLIP: A Difference
// Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2), 2020; "ref.
// code" is NVIDIA's reference implementation, github.com/NVlabs/flip (cpp FLIP.h, python
// flip_api.py), read to check every constant and the order of operations. The code below is our
// own: separable passes in double precision instead of the reference's 2-D float kernels.

namespace fovlab::metrics {
namespace {

using detail::require_same_size;
using detail::require_valid_layout;
using detail::size_text;

using Vec3 = std::array<double, 3>;
using Mat3 = std::array<Vec3, 3>;

// --- Colour spaces --------------------------------------------------------------------------------

// sRGB transfer function, IEC 61966-2-1 (the paper's colour pipeline starts from linear RGB; ref.
// code srgb2linrgb uses the same threshold 0.04045, slope 12.92 and exponent 2.4).
double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4); }

// Linear sRGB -> CIE XYZ for D65, as exact fractions (ref. code LinearRGB2XYZ, citing
// image-engineering.de technote 958). Rows sum to the reference white below.
constexpr Mat3 kRgbToXyz = {{{10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
                             {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
                             {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}}};

Vec3 multiply(const Mat3& m, const Vec3& v) {
  return {m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2], m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
          m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2]};
}

// The exact inverse (adjugate / determinant) of kRgbToXyz, computed in double. The ref. code
// hard-codes its nine-digit rounding (3.241003233, -1.537398969, ...).
Mat3 inverse(const Mat3& m) {
  const double c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const double c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const double c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const double det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  return {{{c00 / det, (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det, (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det},
           {c01 / det, (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det, (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det},
           {c02 / det, (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det, (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det}}};
}

struct ColourSpace {
  Mat3 xyz_to_rgb = inverse(kRgbToXyz);
  // Reference white: the XYZ of linear RGB (1, 1, 1), i.e. D65 normalised to Y = 1
  // (0.950428545, 1, 1.088900371 in the ref. code).
  Vec3 white = multiply(kRgbToXyz, {1.0, 1.0, 1.0});
};

const ColourSpace& colour_space() {
  static const ColourSpace space;
  return space;
}

// XYZ -> YCxCz, the linearised CIELAB opponent space of Flohr, Kolpatzik, Balasubramanian, Carrara,
// Bouman, Allebach (1993) used by the paper (colour pipeline): the CIELAB formulas without the cube root.
Vec3 xyz_to_ycxcz(const Vec3& xyz) {
  const Vec3& w = colour_space().white;
  const double x = xyz[0] / w[0], y = xyz[1] / w[1], z = xyz[2] / w[2];
  return {116.0 * y - 16.0, 500.0 * (x - y), 200.0 * (y - z)};
}

Vec3 ycxcz_to_xyz(const Vec3& o) {
  const Vec3& w = colour_space().white;
  const double y = (o[0] + 16.0) / 116.0;
  return {(y + o[1] / 500.0) * w[0], y * w[1], (y - o[2] / 200.0) * w[2]};
}

// CIE 1976 L*a*b* with the exact CIE break point (6/29)^3 and slope 1/(3 (6/29)^2)
// (ref. code flip_api.py xyz2lab; the C++ ref. code rounds them to 0.008856 and 7.787).
double lab_f(double t) {
  constexpr double delta = 6.0 / 29.0;
  return t > delta * delta * delta ? std::cbrt(t) : t / (3.0 * delta * delta) + 4.0 / 29.0;
}

Vec3 xyz_to_lab(const Vec3& xyz) {
  const Vec3& w = colour_space().white;
  const double fx = lab_f(xyz[0] / w[0]), fy = lab_f(xyz[1] / w[1]), fz = lab_f(xyz[2] / w[2]);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

// Hunt adjustment (paper, colour pipeline): chroma scaled by 0.01 L*, so that colours of the same
// chromaticity look more different when brighter.
Vec3 hunt_adjust(const Vec3& lab) { return {lab[0], 0.01 * lab[0] * lab[1], 0.01 * lab[0] * lab[2]}; }

// HyAB distance of Abasi, Amani Tehran, Fairchild (2020) (paper, colour pipeline): city-block in L*,
// Euclidean in (a*, b*).
double hyab(const Vec3& p, const Vec3& q) { return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]); }

// --- Constants of the metric ----------------------------------------------------------------------

// Contrast sensitivity functions of the opponent channels, each a sum of two Gaussians in the
// spatial domain, S(x) = a1 sqrt(pi / b1) exp(-pi^2 x^2 / b1) + a2 sqrt(pi / b2) exp(-pi^2 x^2 / b2)
// with x in degrees (paper, spatial filtering, and its table of CSF parameters; ref. code
// generateSpatialFilter).
// b2 = 1e-5 where a2 = 0 only avoids a division by zero in the ref. code and has no effect.
struct CsfParameters {
  double a1, b1, a2, b2;
};
constexpr CsfParameters kCsfAchromatic = {1.0, 0.0047, 0.0, 1e-5};
constexpr CsfParameters kCsfRedGreen = {1.0, 0.0053, 0.0, 1e-5};
constexpr CsfParameters kCsfBlueYellow = {34.1, 0.04, 13.5, 0.025};
// All three filters share one radius, 3 standard deviations of the widest Gaussian: the largest
// b is 0.04 (paper, spatial filtering; ref. code: maxScaleParameter).
constexpr double kCsfLargestB = 0.04;

constexpr double kQc = 0.7;   // colour difference exponent (paper, colour pipeline; ref. code gqc)
constexpr double kPc = 0.4;   // break point of the error redistribution, as a fraction of cmax (gpc)
constexpr double kPt = 0.95;  // error at the break point (paper, colour pipeline; ref. code gpt)
// Edge and point detectors: Gaussian derivatives whose peak-to-trough distance (two standard
// deviations) is w = 0.082 degrees (paper, feature pipeline; ref. code gw).
constexpr double kDetectorWidthDeg = 0.082;
constexpr double kQf = 0.5;  // feature difference exponent (paper, feature pipeline; ref. code gqf)

// --- Separable filtering with replicated borders --------------------------------------------------

// One channel of the image, row-major, double precision.
using Plane = std::vector<double>;

// Correlates `in` (width x height) with the separable kernel kx(i) * ky(j), both of odd length
// 2r + 1 and indexed from -r, reading outside the image from the nearest edge pixel ("replicate",
// as the ref. code's clamped indices and OpenCV's BORDER_REPLICATE). Clamping x and y separately
// makes the two passes equal to the 2-D correlation.
Plane correlate_separable(const Plane& in, int width, int height, const std::vector<double>& kx,
                          const std::vector<double>& ky) {
  const int rx = static_cast<int>(kx.size() / 2);
  const int ry = static_cast<int>(ky.size() / 2);
  const auto w = static_cast<std::size_t>(width);
  Plane rows(in.size());
  for (int y = 0; y < height; ++y) {
    const double* src = in.data() + static_cast<std::size_t>(y) * w;
    double* dst = rows.data() + static_cast<std::size_t>(y) * w;
    for (int x = 0; x < width; ++x) {
      double sum = 0.0;
      for (int i = -rx; i <= rx; ++i) {
        const int xx = std::clamp(x + i, 0, width - 1);
        sum += kx[static_cast<std::size_t>(i + rx)] * src[xx];
      }
      dst[x] = sum;
    }
  }
  Plane out(in.size());
  for (int y = 0; y < height; ++y) {
    double* dst = out.data() + static_cast<std::size_t>(y) * w;
    for (int j = -ry; j <= ry; ++j) {
      const int yy = std::clamp(y + j, 0, height - 1);
      const double weight = ky[static_cast<std::size_t>(j + ry)];
      const double* src = rows.data() + static_cast<std::size_t>(yy) * w;
      for (int x = 0; x < width; ++x) dst[x] += weight * src[x];
    }
  }
  return out;
}

// --- Colour pipeline ------------------------------------------------------------------------------

int csf_radius(double ppd) {
  return static_cast<int>(std::ceil(3.0 * std::sqrt(kCsfLargestB / (2.0 * std::numbers::pi * std::numbers::pi)) * ppd));
}

// exp(-pi^2 x^2 / b) at x = i / ppd degrees, i = -r..r: one factor of a separable 2-D Gaussian.
std::vector<double> csf_gaussian(double b, double ppd, int radius) {
  std::vector<double> g(static_cast<std::size_t>(2 * radius + 1));
  for (int i = -radius; i <= radius; ++i) {
    const double x = i / ppd;
    g[static_cast<std::size_t>(i + radius)] = std::exp(-std::numbers::pi * std::numbers::pi * x * x / b);
  }
  return g;
}

double sum(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

// Filters one opponent channel with its CSF kernel, normalised to sum 1 over the (2r + 1)^2 square
// as in the paper and the ref. code. Each Gaussian term is separable:
// exp(-pi^2 (x^2 + y^2) / b) = g(x) g(y), and its 2-D sum is (sum g)^2.
Plane csf_filter(const Plane& channel, int width, int height, const CsfParameters& p, double ppd) {
  const int radius = csf_radius(ppd);
  const std::vector<double> g1 = csf_gaussian(p.b1, ppd, radius);
  const double w1 = p.a1 * std::sqrt(std::numbers::pi / p.b1);
  const double s1 = sum(g1);
  if (p.a2 == 0.0) {
    std::vector<double> k = g1;
    for (double& v : k) v /= s1;  // w1 cancels in the normalisation
    return correlate_separable(channel, width, height, k, k);
  }
  const std::vector<double> g2 = csf_gaussian(p.b2, ppd, radius);
  const double w2 = p.a2 * std::sqrt(std::numbers::pi / p.b2);
  const double s2 = sum(g2);
  const double total = w1 * s1 * s1 + w2 * s2 * s2;
  const Plane f1 = correlate_separable(channel, width, height, g1, g1);
  const Plane f2 = correlate_separable(channel, width, height, g2, g2);
  Plane out(channel.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = (w1 * f1[i] + w2 * f2[i]) / total;
  return out;
}

// The three YCxCz planes of an image.
struct Opponent {
  Plane y, cx, cz;
};

// Paper, colour pipeline, after the spatial filter: back to linear RGB, clamped to [0, 1] (the filtered
// colour may leave the gamut), then L*a*b* and the Hunt adjustment.
std::vector<Vec3> preprocess(const Opponent& o, int width, int height, double ppd) {
  const Plane y = csf_filter(o.y, width, height, kCsfAchromatic, ppd);
  const Plane cx = csf_filter(o.cx, width, height, kCsfRedGreen, ppd);
  const Plane cz = csf_filter(o.cz, width, height, kCsfBlueYellow, ppd);
  std::vector<Vec3> out(y.size());
  const Mat3& to_rgb = colour_space().xyz_to_rgb;
  for (std::size_t i = 0; i < out.size(); ++i) {
    Vec3 rgb = multiply(to_rgb, ycxcz_to_xyz({y[i], cx[i], cz[i]}));
    for (double& c : rgb) c = std::clamp(c, 0.0, 1.0);
    out[i] = hunt_adjust(xyz_to_lab(multiply(kRgbToXyz, rgb)));
  }
  return out;
}

// Paper, colour metric: the HyAB distance raised to qc, mapped piecewise-linearly to [0, 1]: [0, pc cmax)
// onto [0, pt), [pc cmax, cmax] onto [pt, 1].
double redistribute(double hyab_distance, double cmax) {
  const double e = std::pow(hyab_distance, kQc);
  const double break_point = kPc * cmax;
  if (e < break_point) return kPt / break_point * e;
  return kPt + (e - break_point) / (cmax - break_point) * (1.0 - kPt);
}

// --- Feature pipeline -----------------------------------------------------------------------------

// One factor pair of a detector: the derivative factor along the filtering direction (normalised
// so its positive weights sum to 1 and its negative weights to -1) and the Gaussian across it
// (normalised to sum 1). Their outer product is the paper's 2-D kernel with positive weights
// summing to 1 and negative to -1: the sign depends only on the derivative factor.
struct Detector {
  std::vector<double> along, across;
};

Detector make_detector(double ppd, bool point) {
  const double sd = 0.5 * kDetectorWidthDeg * ppd;  // in pixels (paper, feature pipeline)
  const int radius = static_cast<int>(std::ceil(3.0 * sd));
  Detector d;
  d.along.resize(static_cast<std::size_t>(2 * radius + 1));
  d.across.resize(d.along.size());
  double positive = 0.0, negative = 0.0, gauss = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    const double x = i;
    const double g = std::exp(-x * x / (2.0 * sd * sd));
    // Edge: first derivative of the Gaussian, -x g; point: second derivative, (x^2 / sd^2 - 1) g.
    const double v = point ? (x * x / (sd * sd) - 1.0) * g : -x * g;
    d.along[static_cast<std::size_t>(i + radius)] = v;
    d.across[static_cast<std::size_t>(i + radius)] = g;
    if (v > 0.0) positive += v;
    if (v < 0.0) negative -= v;
    gauss += g;
  }
  for (double& v : d.along) {
    if (v > 0.0) v /= positive;
    if (v < 0.0) v /= negative;
  }
  for (double& g : d.across) g /= gauss;
  return d;
}

// Magnitude of the detector's response: the norm of the horizontal and vertical filter outputs.
Plane feature_magnitude(const Plane& luminance, int width, int height, const Detector& d) {
  const Plane horizontal = correlate_separable(luminance, width, height, d.along, d.across);
  const Plane vertical = correlate_separable(luminance, width, height, d.across, d.along);
  Plane out(luminance.size());
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::hypot(horizontal[i], vertical[i]);
  return out;
}

// --- Input ----------------------------------------------------------------------------------------

// sRGB-encoded image -> YCxCz (paper, colour pipeline: sRGB -> linear RGB -> XYZ -> YCxCz).
Opponent to_opponent(const Image& image) {
  const std::size_t n = image.pixel_count();
  const auto stride = static_cast<std::size_t>(image.channels);
  Opponent o{Plane(n), Plane(n), Plane(n)};
  for (std::size_t i = 0; i < n; ++i) {
    const float* p = image.pixels.data() + i * stride;
    Vec3 encoded = image.channels == 1 ? Vec3{p[0], p[0], p[0]} : Vec3{p[0], p[1], p[2]};
    for (double v : encoded) {
      if (!(v >= 0.0 && v <= 1.0)) {
        throw std::invalid_argument("FLIP: colour sample " + std::to_string(v) + " at pixel " + std::to_string(i) +
                                    " is outside [0, 1]; expected sRGB-encoded values in [0, 1]");
      }
    }
    Vec3 linear{};
    for (std::size_t c = 0; c < 3; ++c) linear[c] = srgb_to_linear(encoded[c]);
    const Vec3 opp = xyz_to_ycxcz(multiply(kRgbToXyz, linear));
    o.y[i] = opp[0];
    o.cx[i] = opp[1];
    o.cz[i] = opp[2];
  }
  return o;
}

}  // namespace

double flip_cmax() {
  const Vec3 green = hunt_adjust(xyz_to_lab(multiply(kRgbToXyz, {0.0, 1.0, 0.0})));
  const Vec3 blue = hunt_adjust(xyz_to_lab(multiply(kRgbToXyz, {0.0, 0.0, 1.0})));
  return std::pow(hyab(green, blue), kQc);
}

FlipResult flip(const Image& reference, const Image& test, double pixels_per_degree) {
  require_valid_layout(reference);
  require_valid_layout(test);
  require_same_size(reference, test);
  if ((reference.channels == 1) != (test.channels == 1)) {
    throw std::invalid_argument("FLIP: cannot compare a grey image with a colour image");
  }
  if (reference.pixel_count() == 0) throw std::invalid_argument("FLIP: empty images");
  if (!std::isfinite(pixels_per_degree) || pixels_per_degree <= 0.0) {
    throw std::invalid_argument("FLIP: pixels_per_degree " + exact_number_text(pixels_per_degree) +
                                " must be positive and finite");
  }
  const int width = reference.width;
  const int height = reference.height;
  const double ppd = pixels_per_degree;

  const Opponent ref = to_opponent(reference);
  const Opponent tst = to_opponent(test);

  // Colour pipeline.
  const std::vector<Vec3> ref_lab = preprocess(ref, width, height, ppd);
  const std::vector<Vec3> tst_lab = preprocess(tst, width, height, ppd);
  const double cmax = flip_cmax();

  // Feature pipeline (paper) on the unfiltered achromatic channel, normalised to [0, 1]
  // by (Y + 16) / 116 (the erratum's division by 116; that is Y / Y_white).
  Plane ref_lum(ref.y.size()), tst_lum(tst.y.size());
  for (std::size_t i = 0; i < ref_lum.size(); ++i) {
    ref_lum[i] = (ref.y[i] + 16.0) / 116.0;
    tst_lum[i] = (tst.y[i] + 16.0) / 116.0;
  }
  const Detector edge = make_detector(ppd, false);
  const Detector point = make_detector(ppd, true);
  const Plane ref_edges = feature_magnitude(ref_lum, width, height, edge);
  const Plane tst_edges = feature_magnitude(tst_lum, width, height, edge);
  const Plane ref_points = feature_magnitude(ref_lum, width, height, point);
  const Plane tst_points = feature_magnitude(tst_lum, width, height, point);

  FlipResult result;
  result.error_map = Image(width, height, 1);
  double total = 0.0;
  for (std::size_t i = 0; i < ref_lab.size(); ++i) {
    const double colour_error = redistribute(hyab(ref_lab[i], tst_lab[i]), cmax);
    const double feature_difference =
        std::max(std::abs(ref_edges[i] - tst_edges[i]), std::abs(ref_points[i] - tst_points[i]));
    // Normalised to [0, 1] by 1 / sqrt(2), the largest possible difference of two magnitudes
    // (paper, feature pipeline), then raised to qf.
    const double feature_error = std::pow(feature_difference / std::numbers::sqrt2, kQf);
    // Paper, final error: the feature error raises the colour error towards 1.
    const double error = std::pow(colour_error, 1.0 - feature_error);
    result.error_map.pixels[i] = static_cast<float>(error);
    total += error;
  }
  result.mean_flip = total / static_cast<double>(ref_lab.size());
  return result;
}

}  // namespace fovlab::metrics
