#include "app/sampling_flags.h"

#include <algorithm>
#include <cmath>

#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab::app {

namespace {
// The flag each SamplingSettings field is set by, for errors raised by make_sampling_map.
struct FieldFlag {
  const char* field;
  const char* flag;
};
constexpr FieldFlag kFieldFlags[] = {{"sigma", "--sigma"},
                                     {"focal_share_x", "--fx"},
                                     {"focal_share_y", "--fy"},
                                     {"alpha", "--alpha"},
                                     {"inner_radius_deg", "--inner-radius-deg"},
                                     {"outer_radius_deg", "--outer-radius-deg"},
                                     {"middle_pixel_size_px", "--middle-pixel-size"},
                                     {"outer_pixel_size_px", "--outer-pixel-size"},
                                     {"blend_band_deg", "--blend-band-deg"},
                                     {"min_probability", "--min-probability"}};
}  // namespace

void add_sampling_flags(CLI::App& command, SamplingSettings& settings, bool focal_shares) {
  command.add_option("--sigma", settings.sigma,
                     "Sampling: screen over buffer size per axis (rmfr, kfr); --equalise's target: rmfr at this sigma");
  if (focal_shares) {
    command.add_option("--fx", settings.focal_share_x, "Sampling: rmfr's f_x as a share of the width (0.001 to 1)");
    command.add_option("--fy", settings.focal_share_y, "Sampling: rmfr's f_y as a share of the height (0.001 to 1)");
  }
  command.add_option("--alpha", settings.alpha, "Sampling: kfr's kernel exponent");
  command.add_option("--inner-radius-deg", settings.inner_radius_deg,
                     "Sampling: hyperbolic and linear r1, an eccentricity (radius) in degrees");
  command.add_option("--outer-radius-deg", settings.outer_radius_deg,
                     "Sampling: hyperbolic and linear r2, an eccentricity (radius) in degrees");
  command.add_option("--middle-pixel-size", settings.middle_pixel_size_px, "Sampling: hyperbolic s2 in screen pixels");
  command.add_option("--outer-pixel-size", settings.outer_pixel_size_px, "Sampling: hyperbolic s3 in screen pixels");
  command.add_option("--blend-band-deg", settings.blend_band_deg,
                     "Sampling: hyperbolic fade at each layer's border, in degrees of eccentricity");
  command.add_option("--min-probability", settings.min_probability, "Sampling: linear p_min beyond r2");
  command.add_option("--sample-seed", settings.seed, "Sampling: seed of the linear model's per-pixel thresholds");
  command
      .add_option_function<std::string>(
          "--resample",
          [&settings](const std::string& name) {
            settings.filter = name == "lanczos" ? ResampleFilter::lanczos2 : ResampleFilter::bilinear;
          },
          "Sampling: how pass 2 reads the samples (rmfr, kfr, hyperbolic): bilinear or lanczos")
      ->check(CLI::IsMember({"bilinear", "lanczos"}));
  command
      .add_option_function<std::string>(
          "--equalise",
          [&settings](const std::string& name) {
            settings.equalise = name == "density" ? Equalise::density : Equalise::samples;
          },
          "Sampling: solve hyperbolic s3 / linear p_min / kfr's buffer sigma to match rmfr at --sigma on this display: "
          "alone or 'samples': as many shaded samples; 'density' (hyperbolic, linear): mean density 1/sigma^2")
      ->expected(0, 1)
      ->default_str("samples")
      ->check(CLI::IsMember({"samples", "density"}));
}

std::vector<std::string> given_sampling_only_flags(const CLI::App& command) {
  std::vector<std::string> given;
  for (const CLI::Option* option : command.get_options())
    if (option->count() > 0 && option->get_description().rfind("Sampling:", 0) == 0)
      given.push_back(option->get_name());
  return given;
}

namespace {
using M = SamplingModel;

// The models that use a sampling flag: what refuse_flags_unused_by allows, and what a sweep's
// command writes.
std::vector<M> users_of(const std::string& flag) {
  if (flag == "--fx" || flag == "--fy") return {M::rectangular};
  if (flag == "--alpha") return {M::kernel_log_polar};
  if (flag == "--inner-radius-deg" || flag == "--outer-radius-deg") return {M::hyperbolic, M::linear};
  if (flag == "--middle-pixel-size" || flag == "--outer-pixel-size" || flag == "--blend-band-deg")
    return {M::hyperbolic};
  if (flag == "--min-probability" || flag == "--sample-seed") return {M::linear};
  if (flag == "--equalise") return {M::hyperbolic, M::linear, M::kernel_log_polar};
  if (flag == "--resample") return {M::rectangular, M::hyperbolic, M::kernel_log_polar};
  return {M::rectangular, M::hyperbolic, M::linear, M::kernel_log_polar};  // --sigma
}

// " --equalise" (samples) or " --equalise density".
std::string equalise_flag_text(Equalise equalise) {
  return equalise == Equalise::density ? " --equalise density" : " --equalise";
}

bool used_by_any(const std::string& flag, const std::vector<M>& models) {
  const std::vector<M> users = users_of(flag);
  return std::any_of(models.begin(), models.end(),
                     [&](M model) { return std::find(users.begin(), users.end(), model) != users.end(); });
}
}  // namespace

void refuse_flags_unused_by(const std::vector<std::string>& given, const std::vector<SamplingModel>& models) {
  const auto names = [](const std::vector<M>& list) {
    std::string text;
    for (M model : list) text += (text.empty() ? "" : ", ") + std::string(sampling_model_name(model));
    return text;
  };
  for (const std::string& flag : given)
    if (!used_by_any(flag, models))
      throw InputError(flag + ": " + names(models) + (models.size() > 1 ? " do" : " does") + " not use it; it is for " +
                       names(users_of(flag)));
}

SamplingMap parse_sampling(SamplingModel model, const SamplingSettings& settings, const FoveationSettings& foveation) {
  SamplingSettings with_model = settings;
  with_model.model = model;
  try {
    return make_sampling_map(with_model, foveation.display, foveation.gaze_x_px, foveation.gaze_y_px);
  } catch (const SettingError& error) {
    for (const FieldFlag& field : kFieldFlags)
      if (error.field == field.field) throw InputError(std::string(field.flag) + error.detail);
    throw;
  }
}

std::string sampling_flags_text(SamplingModel model, const SamplingSettings& s) {
  const auto number = [](double value) { return exact_number_text(value); };  // reproduces the settings
  std::string text = "--sigma " + number(s.sigma);
  switch (model) {
    case SamplingModel::rectangular:
      text += " --fx " + number(s.focal_share_x) + " --fy " + number(s.focal_share_y);
      break;
    case SamplingModel::kernel_log_polar:
      text += " --alpha " + number(s.alpha);
      break;
    case SamplingModel::hyperbolic:
      text += " --inner-radius-deg " + number(s.inner_radius_deg) + " --outer-radius-deg " +
              number(s.outer_radius_deg) + " --middle-pixel-size " + number(s.middle_pixel_size_px) +
              " --outer-pixel-size " + number(s.outer_pixel_size_px) + " --blend-band-deg " + number(s.blend_band_deg);
      break;
    case SamplingModel::linear:
      text += " --inner-radius-deg " + number(s.inner_radius_deg) + " --outer-radius-deg " +
              number(s.outer_radius_deg) + " --min-probability " + number(s.min_probability) + " --sample-seed " +
              std::to_string(s.seed);
      break;
  }
  if (s.equalise != Equalise::off && model != SamplingModel::rectangular) text += equalise_flag_text(s.equalise);
  if (s.filter != ResampleFilter::bilinear && model != SamplingModel::linear)
    text += std::string(" --resample ") + resample_filter_name(s.filter);
  return text;
}

std::string all_sampling_flags_text(const SamplingSettings& s, const std::vector<SamplingModel>& models,
                                    const std::string& focal_shares) {
  const auto number = [](double value) { return exact_number_text(value); };      // reproduces the settings
  const auto used = [&](const char* flag) { return used_by_any(flag, models); };  // a flag no model uses is refused
  std::string text = "--sigma " + number(s.sigma);
  if (used("--fx"))
    text += " " + (focal_shares.empty() ? "--fx " + number(s.focal_share_x) + " --fy " + number(s.focal_share_y)
                                        : focal_shares);
  if (used("--alpha")) text += " --alpha " + number(s.alpha);
  if (used("--inner-radius-deg"))
    text += " --inner-radius-deg " + number(s.inner_radius_deg) + " --outer-radius-deg " + number(s.outer_radius_deg);
  if (used("--middle-pixel-size"))
    text += " --middle-pixel-size " + number(s.middle_pixel_size_px) + " --outer-pixel-size " +
            number(s.outer_pixel_size_px) + " --blend-band-deg " + number(s.blend_band_deg);
  if (used("--min-probability"))
    text += " --min-probability " + number(s.min_probability) + " --sample-seed " + std::to_string(s.seed);
  if (s.equalise != Equalise::off && used("--equalise")) text += equalise_flag_text(s.equalise);
  if (used("--resample")) text += std::string(" --resample ") + resample_filter_name(s.filter);
  return text;
}

std::string sampling_summary(const SamplingMap& map) {
  const double pixels = double(screen_width_px(map)) * double(screen_height_px(map));
  std::string text = std::string(sampling_model_name(model_of(map))) + ": " +
                     format_number(100.0 * double(shaded_samples(map)) / pixels, 3) +
                     " % of pixels shaded (theoretical speed-up " + format_number(theoretical_speedup(map), 3) +
                     ", effective " + format_number(effective_speedup(map), 3) + "), mean density " +
                     format_number(mean_density(map), 3);
  if (const auto* layers = std::get_if<HyperbolicLayers>(&map))
    text += ", outer pixel " + format_number(layers->layers[2].pixel_size_px, 4) + " px";
  if (const auto* linear = std::get_if<LinearFalloff>(&map))
    text += ", p_min " + format_number(linear->min_probability, 4);
  return text;
}

}  // namespace fovlab::app
