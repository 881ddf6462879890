#include "app/cli_support.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <cstdlib>
#include <map>
#include <stdexcept>

#include "app/display_flags.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "study/stimulus/render_method.h"

namespace fovlab::app {

vk::ContextOptions context_options(const std::string& device_selector) {
  return {device_selector, vk::validation_requested_by_default()};
}

PartOfN parse_part_of_n(const std::string& text, const std::string& flag, const std::string& example) {
  const auto parts = split_pair(text, "/");
  const auto index = parts ? parse_finite_number(parts->first) : std::nullopt;
  const auto count = parts ? parse_finite_number(parts->second) : std::nullopt;
  if (!index || !count || *count < 1 || *count > 100000 || *index < 0 || *index >= *count ||
      *index != std::floor(*index) || *count != std::floor(*count))
    fail_flag(flag, "I/N with whole numbers 0 <= I < N (" + example + ")", text);
  return {int(*index), int(*count)};
}

std::string duration_text(double seconds) {
  const long total = std::lround(std::max(0.0, seconds));
  char text[32];
  if (total >= 3600) std::snprintf(text, sizeof text, "%ldh%02ldm", total / 3600, (total / 60) % 60);
  else if (total >= 60) std::snprintf(text, sizeof text, "%ldm%02lds", total / 60, total % 60);
  else std::snprintf(text, sizeof text, "%lds", total);
  return text;
}

std::function<void(double)> percent_progress(const std::string& what) {
  struct State {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    int shown = -1;  // the last percent printed
    bool terminal = isatty(STDERR_FILENO) == 1;
  };
  auto state = std::make_shared<State>();
  return [state, what](double share) {
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - state->start).count();
    const int percent = int(std::floor(std::clamp(share, 0.0, 1.0) * 100.0));
    if (elapsed_s < 1.0 || percent == state->shown) return;
    if (!state->terminal && percent < 100 && percent / 10 == std::max(state->shown, 0) / 10 && state->shown >= 0)
      return;
    state->shown = percent;
    const double eta_s = share > 0.0 ? elapsed_s * (1.0 - share) / share : 0.0;
    std::fprintf(stderr, state->terminal ? "\r%s: %3d %%, ETA %s   " : "%s: %d %%, ETA %s\n", what.c_str(), percent,
                 duration_text(eta_s).c_str());
    if (state->terminal && percent == 100) std::fprintf(stderr, "\n");
  };
}

std::function<void(const std::string&)> step_progress(const std::string& what, int total) {
  struct State {
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    int done = 0;
  };
  auto state = std::make_shared<State>();
  return [state, what, total](const std::string& step) {
    ++state->done;
    const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - state->start).count();
    const double eta_s = elapsed_s / state->done * std::max(0, total - state->done);
    std::fprintf(stderr, "%s: %d/%d (%s) after %s, ETA %s\n", what.c_str(), state->done, total, step.c_str(),
                 duration_text(elapsed_s).c_str(), duration_text(eta_s).c_str());
  };
}

bool display_available() {
  const char* x11 = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  return (x11 && *x11) || (wayland && *wayland);
}

void fail_on_validation_messages(const vk::Context& context) {
  if (context.validation_message_count() > 0) {
    throw std::runtime_error(std::to_string(context.validation_message_count()) +
                             " Vulkan validation message(s); see above");
  }
}

void add_trace_options(CLI::App& command, SphereTraceSettings& settings) {
  command.add_option("--time", settings.time_s, "Scene time in seconds (camera path, moving lights)");
  command.add_option("--levels", settings.pyramid_levels, "IPR pyramid levels, 2 to 5 (3: 1/16, 1/4, full)");
  command.add_option("--min-filter", settings.min_filter_size,
                     "IPR/FIPR min-filter size: 1, 3 or 5 (default: each method's own, 1)");
  static const std::map<std::string, CoarseTest> coarse_tests = {
      {coarse_test_name(CoarseTest::centre_ray), CoarseTest::centre_ray},
      {coarse_test_name(CoarseTest::cone), CoarseTest::cone}};
  command
      .add_option(
          "--coarse-test", settings.coarse_test,
          "IPR/FIPR depth levels: cone (the pixel's whole cone: no finer ray starts behind a surface it would hit) "
          "or ray (the paper's centre ray)")
      ->transform(CLI::CheckedTransformer(coarse_tests))
      ->default_str("cone");
  command.add_flag(
      "--full-depth", settings.full_resolution_depth,
      "IPR: a full-resolution depth level (one ray a pixel) before the shaded samples, which start from it");
  command.add_option("--max-steps", settings.max_steps, "Step cap of one ray at one level");
  command.add_option("--hit-threshold", settings.hit_threshold,
                     "Hit when distance < t x pixel angle x this (pixel-footprint epsilon)");
}

PyramidFlagsGiven given_pyramid_flags(const CLI::App& command) {
  return {command.get_option("--min-filter")->count() > 0, command.get_option("--coarse-test")->count() > 0};
}

namespace {

// The flags that set a method's parameters, checked against its descriptor (study/stimulus/
// render_method.h): the config's ranges and allowed values are the command line's too.
void check_flags_against_descriptor(const SphereTraceSettings& settings) {
  const std::optional<RenderMethod> method = find_method(method_name(settings.method));
  if (!method) return;
  const MethodDescriptor& descriptor = describe(*method);
  const FoveationSettings& fov = settings.foveation;
  // Each value also as the flag gave it: the shortest text that reads back as the field's own type
  // (--hit-threshold 0.00001, not the float's 9.9999997473787516e-06).
  struct Flag {
    const char* flag;
    const char* key;
    double value;
    std::string text;
  };
  const auto flag = [](const char* name, const char* key, auto value) {
    return Flag{name, key, double(value), exact_number_text(value)};
  };
  std::vector<Flag> flags = {flag("--spp", "samples_per_pixel", double(settings.samples_per_pixel)),
                             flag("--max-steps", "max_steps", double(settings.max_steps)),
                             flag("--hit-threshold", "hit_threshold", settings.hit_threshold),
                             flag("--levels", "pyramid_levels", double(settings.pyramid_levels)),
                             flag("--min-filter", "min_filter_size", double(settings.min_filter_size))};
  if (settings.method == TraceMethod::foveated_pyramid) {
    flags.push_back(flag("--fovea-deg", "fovea_radius_deg", fov.acuity.fovea_radius_deg));
    if (std::isfinite(fov.acuity.outer_periphery_radius_deg))
      flags.push_back(
          flag("--outer-periphery-deg", "outer_periphery_radius_deg", fov.acuity.outer_periphery_radius_deg));
    flags.push_back(flag("--refresh", "periphery_refresh", double(fov.periphery_refresh)));
    flags.push_back(flag("--periphery-steps", "periphery_steps", double(fov.periphery_steps)));
    flags.push_back(flag("--edge-threshold", "edge_threshold", fov.edge_threshold));
  }
  for (const Flag& given : flags) {
    const ParameterDescriptor* parameter = find_parameter(descriptor, given.key);
    if (!parameter) continue;  // not a parameter of this method (e.g. --levels of gt)
    if (const std::optional<std::string> expected = check_parameter_value(*parameter, given.value))
      throw InputError(
          std::string(given.flag) + " " +
          (parameter->type == ParameterType::choice ? parameter_value_text(*parameter, given.value) : given.text) +
          ": expected " + *expected);
  }
}

}  // namespace

void validate_trace_flags(const SphereTraceSettings& settings) {
  check_flags_against_descriptor(settings);
  static const std::map<std::string, std::string> flag_of_field = {
      {"width", "--width"},
      {"height", "--height"},
      {"samples_per_pixel", "--spp"},
      {kSamplesPerFrameField, "--width x --height x --spp"},
      {"pyramid_levels", "--levels"},
      {"min_filter_size", "--min-filter"},
      {"max_steps", "--max-steps"},
      {"hit_threshold", "--hit-threshold"},
      {"over_relaxation", "--over-relax"},
      {"time_s", "--time"},
      {"fovea_radius_deg", "--fovea-deg"},
      {"outer_periphery_radius_deg", "--outer-periphery-deg"},
      {"periphery_refresh", "--refresh"},
      {"periphery_steps", "--periphery-steps"},
      {"edge_threshold", "--edge-threshold"}};
  try {
    validate(settings);
  } catch (const SettingError& error) {
    const auto flag = flag_of_field.find(error.field);
    if (flag == flag_of_field.end()) throw;
    throw InputError(flag->second + error.detail);
  }
}

}  // namespace fovlab::app
