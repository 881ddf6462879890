#pragma once
// The four foveation models of Ye et al. 2022 (section 5.1) behind one interface: where a frame shades its
// samples, how densely, and what that saves. Each model is a plain struct; SamplingMap holds one.
//   - rectangular (RMFR, foveation/rectangular_mapping.h): a buffer sigma times smaller per axis,
//     each axis warped towards the gaze;
//   - kernel log-polar (KFR, Meng et al. 2018): a buffer of the same size in (log radius)^alpha and
//     angle around the gaze;
//   - hyperbolic (Guenter et al. 2012): three layers around the gaze, of pixel sizes 1, 2 and s3,
//     out to eccentricities r1, r2 and the whole screen, blended at their borders;
//   - linear (Weier et al.): each pixel shaded with a probability that is 1 up to r1 and falls
//     linearly to p_min at r2, the holes filled by pull-push.
// The CPU code here is the reference that the GPU passes (renderer/foveated_sampling/) are tested
// against. Equations, sources and the decisions where the paper is silent: docs/foveation.md,
// "Sampling models".
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "core/render_choices.h"
#include "foveation/display_geometry.h"
#include "foveation/rectangular_mapping.h"

namespace fovlab {

// SamplingModel, its names and sampling_model_name are core/render_choices.h's.

inline constexpr double kKfrMinAlpha = 0.25;
inline constexpr double kKfrMaxAlpha = 8.0;

// KFR's buffer: u = w (ln r / L)^alpha, v = h theta / (2 pi) for the distance r (pixels, at least 1)
// and the angle theta in [0, 2 pi) of a point around the gaze; L = ln of the largest distance from
// the gaze to a screen corner. Inverse: r = exp(L (u / w)^(1 / alpha)). The buffer covers the disc
// of radius e^L, so part of it falls off the screen: a sample further off it than a radial plus a
// tangential spacing is not shaded (closer ones are the bilinear taps of pixels at the edge).
struct KernelLogPolarMapping {
  int screen_width_px = 0, screen_height_px = 0;
  int buffer_width_px = 0, buffer_height_px = 0;  // round(screen / sigma)
  double gaze_x_px = 0.0, gaze_y_px = 0.0;        // on the screen (clamped; NaN: the centre)
  double sigma = 2.6;                             // what the buffer was made with (equalise: solved)
  double alpha = 4.0;
  double log_max_radius = 1.0;  // L

  std::pair<double, double> to_buffer_px(double x_px, double y_px) const;
  std::pair<double, double> to_screen_px(double u_px, double v_px) const;
  // Buffer pixels per screen pixel: w h alpha (ln r / L)^(alpha - 1) / (2 pi L r^2); 0 within one
  // pixel of the gaze (the buffer's first column lies further out, and fills those pixels).
  double density(double x_px, double y_px) const;
  // The samples' spacings on the screen at buffer column u: radial dr/du = r L s^(1/alpha - 1) /
  // (alpha w) (s = u / w) and tangential 2 pi r / h.
  std::pair<double, double> sample_spacings_px(double u_px) const;
  // Whether buffer sample (u, v) is shaded: its centre within the sum of the two spacings of the
  // screen, so that every bilinear tap of every screen pixel is shaded.
  bool sample_shaded(int u, int v) const;
};

KernelLogPolarMapping make_kernel_log_polar_mapping(int screen_width_px, int screen_height_px, double sigma,
                                                    double alpha, double gaze_x_px, double gaze_y_px);

// One layer of the hyperbolic model: a grid of square pixels `pixel_size_px` screen pixels wide,
// aligned to multiples of that size on the screen (so a gaze shift does not shift its samples),
// over the box that holds the layer's eccentricities; columns x rows samples, shaded where the
// layer has weight.
struct HyperbolicLayer {
  double pixel_size_px = 1.0;
  double origin_x_px = 0.0, origin_y_px = 0.0;  // top left of the grid
  int columns = 0, rows = 0;
  double from_deg = 0.0;  // eccentricities where the layer has weight: [from_deg, to_deg]
  double to_deg = 0.0;
};

struct HyperbolicLayers {
  DisplayGeometry display;
  double gaze_x_px = 0.0, gaze_y_px = 0.0;
  double inner_radius_deg = 10.0;         // r1: the inner layer alone within r1 - band
  double middle_radius_deg = 20.0;        // r2
  double blend_band_deg = 1.0;            // each layer fades out over the last band_deg of its radius
  std::array<HyperbolicLayer, 3> layers;  // inner, middle, outer

  // Blend weights of the three layers at a screen point (they sum to 1).
  std::array<double, 3> weights(double x_px, double y_px) const;
  // 1 / s^2 of the layer that covers the point's eccentricity (Figure 11's piecewise density).
  double density(double x_px, double y_px) const;
  // Whether a layer's sample (column, row) is shaded: some screen point within two layer pixels of
  // its centre gives the layer weight (the bilinear taps of every pixel it serves).
  bool sample_needed(int layer, int column, int row) const;
  std::pair<double, double> sample_centre_px(int layer, int column, int row) const;
};

struct LinearFalloff {
  DisplayGeometry display;
  double gaze_x_px = 0.0, gaze_y_px = 0.0;
  double inner_radius_deg = 10.0;  // r1: probability 1 up to here
  double outer_radius_deg = 20.0;  // r2: p_min from here
  double min_probability = 0.047;  // p_min
  uint32_t seed = 0;

  double probability(double x_px, double y_px) const;
  // The probability at a pixel centre of eccentricity `eccentricity` (what probability() computes).
  double probability_at(double eccentricity_deg) const;
  // Pixel (x, y) is shaded when its threshold (foveation_mask.h mask_threshold(seed, 0, x, y)) is
  // below the probability at its centre.
  bool sampled(int x, int y) const;
};

// How pass 2 reads the reduced buffers: ResampleFilter (core/render_choices.h).
const char* resample_filter_name(ResampleFilter filter);  // "bilinear", "lanczos"

using SamplingMap = std::variant<RectangularMapping, HyperbolicLayers, LinearFalloff, KernelLogPolarMapping>;

inline SamplingModel model_of(const SamplingMap& map) { return static_cast<SamplingModel>(map.index()); }
int screen_width_px(const SamplingMap& map);
int screen_height_px(const SamplingMap& map);

// Samples per screen pixel at a point (the model's analytic density).
double density(const SamplingMap& map, double x_px, double y_px);
// The density's mean over the screen's pixel centres.
double mean_density(const SamplingMap& map);
// Samples one frame shades: the buffer's (RMFR), those that serve the screen (KFR sample_shaded),
// the layers' needed samples (hyperbolic), the sampled pixels (linear). What the GPU pass traces.
uint64_t shaded_samples(const SamplingMap& map);
// The speed-up the model is set for: screen over buffer pixels (RMFR, KFR: sigma^2 up to rounding),
// 1 / mean density (hyperbolic, linear).
double theoretical_speedup(const SamplingMap& map);
// Screen pixels over shaded samples: what the shading pass really saves.
double effective_speedup(const SamplingMap& map);

// RMFR's shaded samples at `sigma` on a screen of that size: its buffer, round(W / sigma) x
// round(H / sigma). Equalise's target for the other models, and bench's reference.
uint64_t rmfr_shaded_samples(int screen_width_px, int screen_height_px, double sigma);

// What make_sampling_map equalises a model to, against RMFR at the same sigma on the same display,
// with the gaze where the map is made (docs/foveation.md, "Equal work"):
//   - samples: RMFR's shaded samples (rmfr_shaded_samples), counted as shaded_samples counts them
//     (what the GPU pass shades): hyperbolic s3, linear p_min, KFR its buffer's sigma solved;
//   - density: the theoretical mean density 1 / sigma^2: hyperbolic s3 and linear p_min solved,
//     KFR as given (its buffer is RMFR's by construction). What `equalise` was before log schema 8.
enum class Equalise : uint8_t { off, samples, density };
const char* equalise_name(Equalise equalise);  // "off", "samples", "density"

// Every model's parameters; each model reads its own. Ranges are checked by make_sampling_map.
struct SamplingSettings {
  SamplingModel model = SamplingModel::rectangular;
  double sigma = 2.6;                  // RMFR, KFR: screen over buffer size per axis; equalise: RMFR's, the target
  double focal_share_x = 0.3;          // RMFR: f_x / W
  double focal_share_y = 0.3;          // RMFR: f_y / H
  double alpha = 4.0;                  // KFR: the kernel's exponent
  double inner_radius_deg = 10.0;      // hyperbolic and linear: r1
  double outer_radius_deg = 20.0;      // hyperbolic and linear: r2
  double middle_pixel_size_px = 2.0;   // hyperbolic: s2 (s1 is 1)
  double outer_pixel_size_px = 12.35;  // hyperbolic: s3
  double blend_band_deg = 1.0;         // hyperbolic: width of the fade at each layer's border
  double min_probability = 0.047;      // linear: p_min
  uint32_t seed = 0;                   // linear: the thresholds' seed
  // Hyperbolic: s3, linear: p_min, KFR (samples only): its buffer's sigma solved on this display
  // and gaze (the other parameters as given), as Equalise says. RMFR is the reference.
  Equalise equalise = Equalise::off;
  // Not the map's: how pass 2 reads its samples (RMFR, KFR, hyperbolic).
  ResampleFilter filter = ResampleFilter::bilinear;
};

// The map of one frame. `display` gives the pixel counts (always) and the physical size and
// viewing distance (hyperbolic and linear: their radii are eccentricities). SettingError naming the
// field and the range expected; InputError when equalising cannot reach its target (says why).
SamplingMap make_sampling_map(const SamplingSettings& settings, const DisplayGeometry& display, double gaze_x_px,
                              double gaze_y_px);

// `settings` with equalise's solution in `solved` (a map made from them with equalise on, e.g. with
// the gaze at the centre) fixed: its s3 (hyperbolic), p_min (linear) or sigma (KFR) taken and
// equalise off, so that the maps of other gazes sample alike. Settings without equalise come back
// unchanged.
SamplingSettings with_solved_equalise(SamplingSettings settings, const SamplingMap& solved);

}  // namespace fovlab
