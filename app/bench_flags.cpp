#include "app/bench_flags.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <sstream>
#include <tuple>

#include "app/cli_support.h"
#include "app/display_flags.h"
#include "app/output_options.h"
#include "app/sampling_flags.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/scene/eye_view.h"
#include "renderer/scene/scene_source.h"
#include "study/config/study_config.h"

namespace fovlab::app {

namespace {

constexpr int kMinSsimSidePx = 11;  // SSIM's 11x11 window must fit in the frame

template <typename T>
void refuse_repeats(const std::vector<T>& values, const std::string& flag, const std::string& text) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::find(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), values[i]) !=
        values.begin() + static_cast<std::ptrdiff_t>(i)) {
      fail_flag(flag, "each value once", text);
    }
  }
}

// --methods: each word read once into its method (bench/bench_method.h's table).
std::vector<bench::BenchMethod> parse_methods(const std::vector<std::string>& names) {
  const std::string text = bench::comma_joined(names);
  const std::string expected =
      "a comma-separated list of gt, ipr, fipr, rmfr, hyperbolic, linear and kfr that includes gt (the reference)";
  std::vector<bench::BenchMethod> methods;
  for (const std::string& name : names) {
    const std::optional<bench::BenchMethod> method = bench::parse_bench_method(name);
    if (!method) fail_flag("--methods", expected, text);
    methods.push_back(*method);
  }
  refuse_repeats(names, "--methods", text);
  if (std::find(methods.begin(), methods.end(), bench::BenchMethod::gt) == methods.end())
    fail_flag("--methods", expected, text);
  return methods;
}

std::vector<int> parse_refreshes(const std::vector<std::string>& texts) {
  const std::string text = bench::comma_joined(texts);
  const std::string expected = "periphery refresh periods from 1, 2 and 4 (frames), comma-separated";
  if (texts.empty()) fail_flag("--refresh", expected, text);
  std::vector<int> refreshes;
  for (const std::string& value : texts) {
    if (value != "1" && value != "2" && value != "4") fail_flag("--refresh", expected, text);
    refreshes.push_back(value[0] - '0');
  }
  refuse_repeats(refreshes, "--refresh", text);
  return refreshes;
}

std::vector<double> parse_fovea_degs(const std::vector<std::string>& texts) {
  const std::string text = bench::comma_joined(texts);
  const std::string expected = "foveal eccentricities in degrees from 0 to 180, comma-separated";
  if (texts.empty()) fail_flag("--fovea-deg", expected, text);
  std::vector<double> degrees;
  for (const std::string& value : texts) {
    const std::optional<double> deg = parse_finite_number(value);
    if (!deg || *deg < 0.0 || *deg > 180.0) fail_flag("--fovea-deg", expected, text);
    degrees.push_back(*deg);
  }
  refuse_repeats(degrees, "--fovea-deg", text);
  return degrees;
}

std::vector<double> parse_focal_shares(const std::vector<std::string>& texts, const char* flag) {
  const std::string text = bench::comma_joined(texts);
  const std::string expected = "shares of the screen from 0.001 to 1, comma-separated, none twice";
  std::vector<double> shares;
  for (const std::string& value : texts) {
    const std::optional<double> share = parse_finite_number(value);
    if (!share || *share < kRmfrMinFocalShare || *share > kRmfrMaxFocalShare) fail_flag(flag, expected, text);
    shares.push_back(*share);
  }
  if (shares.empty()) fail_flag(flag, expected, text);
  refuse_repeats(shares, flag, text);
  return shares;
}

std::vector<float> parse_times(const std::vector<std::string>& texts) {
  const std::string text = bench::comma_joined(texts);
  const std::string expected = "scene times in seconds, finite, comma-separated, none twice";
  std::vector<float> times;
  for (const std::string& value : texts) {
    const std::optional<double> time = parse_finite_number(value);
    if (!time || std::abs(*time) > 1e6) fail_flag("--times", expected, text);
    times.push_back(static_cast<float>(*time));
  }
  if (times.empty()) fail_flag("--times", expected, text);
  refuse_repeats(times, "--times", text);
  return times;
}

// One eye of --headset: its name, its head-locked view and the flag naming the config.
struct HeadsetEye {
  std::string name;  // "left", "right"
  EyeView view;
  std::string headset_flag;  // "--headset CONFIG"
};

bench::BenchOptions read_bench_flags_for(const BenchFlags& flags, const HeadsetEye* eye);

}  // namespace

bench::BenchOptions read_bench_flags(const BenchFlags& flags) {
  const std::vector<bench::BenchOptions> eyes = read_bench_flags_per_eye(flags);
  if (eyes.size() != 1) throw InputError("--eye " + flags.eye + ": expected left or right here (one sweep, one eye)");
  return eyes.front();
}

std::vector<bench::BenchOptions> read_bench_flags_per_eye(const BenchFlags& flags) {
  if (flags.headset.empty()) {
    if (flags.eye_given) throw InputError("--eye " + flags.eye + ": only with --headset CONFIG (a headset's eyes)");
    return {read_bench_flags_for(flags, nullptr)};
  }
  if (!flags.headset_flags_given.empty())
    throw InputError(flags.headset_flags_given.front() +
                     ": not with --headset (its config gives each eye's size and view)");
  if (!flags.cells.empty())
    throw InputError("--cells " + flags.cells + ": not with --headset (an eye's sweep runs whole)");
  if (flags.eye != "left" && flags.eye != "right" && flags.eye != "both")
    fail_flag("--eye", "left, right or both", flags.eye);
  const StudyConfig config = parse_study_config_file(flags.headset, renderer_scene_catalog());
  if (config.display.kind != DisplayKind::openxr)
    throw InputError("--headset " + flags.headset + ": [display] kind is \"" + display_kind_name(config.display.kind) +
                     "\"; expected a headset's config ([display] kind = \"openxr\")");
  const HeadsetDisplayConfig& headset = config.display.headset;
  std::vector<bench::BenchOptions> eyes;
  for (const bool left : {true, false}) {
    const std::string name = left ? "left" : "right";
    if (flags.eye != "both" && flags.eye != name) continue;
    // The views a session renders from and the pre-rendered frames are made for (headset_eye_views).
    const HeadsetEye eye{name, headset_eye_views(headset)[left ? 0 : 1], "--headset " + flags.headset};
    BenchFlags eye_flags = flags;
    eye_flags.settings.width = headset.eye_width_px;
    eye_flags.settings.height = headset.eye_height_px;
    eye_flags.settings.eye = eye.view;
    eyes.push_back(read_bench_flags_for(eye_flags, &eye));
  }
  return eyes;
}

namespace {

bench::BenchOptions read_bench_flags_for(const BenchFlags& flags, const HeadsetEye* eye) {
  bench::BenchOptions options;
  if (!flags.cells.empty()) {
    const PartOfN given = parse_part_of_n(flags.cells, "--cells", "e.g. 1/4: units 1, 5, 9, ... of the sweep");
    options.part = bench::SweepPart{given.index, given.count};
    if (flags.json.empty())
      throw InputError("--cells " + flags.cells + ": needs --json PART.json (fovlab bench-merge joins the parts)");
    if (!flags.out_dir.empty())
      throw InputError(
          "--out-dir: not with --cells (a part's tables and charts are not the sweep's); give --out-dir "
          "to fovlab bench-merge");
  }
  if (flags.repeats < 1 || flags.repeats > 1000) {
    throw InputError("--repeats " + std::to_string(flags.repeats) + ": expected 1 to 1000");
  }
  options.methods = parse_methods(flags.methods);
  const auto has = [&](bench::BenchMethod method) {
    return std::find(options.methods.begin(), options.methods.end(), method) != options.methods.end();
  };
  const bool fipr = has(bench::BenchMethod::fipr);
  std::vector<SamplingModel> sampling_models;  // in the order given
  for (bench::BenchMethod method : options.methods)
    if (const std::optional<SamplingModel> model = bench::sampling_model_of(method)) sampling_models.push_back(*model);
  if (!fipr && !flags.fipr_flags_given.empty()) {
    throw InputError(flags.fipr_flags_given.front() + ": only FIPR uses it; add fipr to --methods (e.g. gt,ipr,fipr)");
  }
  if (sampling_models.empty() && !flags.sampling_flags_given.empty()) {
    throw InputError(flags.sampling_flags_given.front() +
                     ": only the sampling models use it; add rmfr, hyperbolic, linear or kfr to --methods");
  }
  refuse_flags_unused_by(flags.sampling_flags_given, sampling_models);
  const int width = flags.settings.width;
  const int height = flags.settings.height;
  for (int spp : flags.spps) {
    SphereTraceSettings check = flags.settings;
    check.samples_per_pixel = spp;
    validate_trace_flags(check);
  }
  if (width < kMinSsimSidePx || height < kMinSsimSidePx) {
    throw InputError("--width " + std::to_string(width) + " --height " + std::to_string(height) +
                     ": expected at least 11x11 pixels (the SSIM window)");
  }
  if (flags.foveation.display.gaze == "none") {
    fail_flag("--gaze", "a gaze point X,Y (FPSNR and FIPR's mask need one; left out: the centre)", "none");
  }
  if (!flags.times.empty() && flags.time_given) {
    throw InputError("--time, --times: expected one of them (one scene time, or a comma-separated list)");
  }
  if (!flags.times.empty()) options.times_s = parse_times(flags.times);
  // With an eye, eccentricity is the eye's: its off-axis image plane, the gaze at its principal
  // point unless --gaze gives one (in its pixels), whatever display the flags would assume.
  const auto foveation_of = [&](const FoveationFlags& given) {
    FoveationSettings settings = parse_foveation(given, width, height);
    if (!eye) return settings;
    settings.display = eye_display(eye->view, width, height);
    settings.gaze_x_px = settings.display.principal_point_x_px();
    settings.gaze_y_px = settings.display.principal_point_y_px();
    if (!given.display.gaze.empty())
      std::tie(settings.gaze_x_px, settings.gaze_y_px) = parse_gaze(given.display.gaze, width, height);
    return settings;
  };
  const FoveationSettings base = foveation_of(flags.foveation);
  options.display = base.display;
  options.gaze_x_px = base.gaze_x_px;
  options.gaze_y_px = base.gaze_y_px;
  options.display_line = display_line(
      options.display, has_display(flags.foveation.display) ? "" : "FIPR's default, a 24-inch display at 600 mm");
  options.display_flags = display_flags_text(flags.foveation.display);
  if (eye) {
    options.eye_name = eye->name;
    options.headset_flags = eye->headset_flag;
    options.display_flags =
        "--eye " + eye->name + (flags.foveation.display.gaze.empty() ? "" : " --gaze " + flags.foveation.display.gaze);
    options.display_line =
        eye->name + " eye " + std::to_string(width) + "x" + std::to_string(height) + " px, " +
        field_of_view_text(eye->view.field_of_view) + ", at " + format_number(eye->view.position_in_head[0], 6) +
        " m along the head's x; " + format_number(options.display.pixels_per_degree_at_principal_point(), 4) +
        " px/deg at its principal point (" + format_number(options.display.principal_point_x_px(), 6) + ", " +
        format_number(options.display.principal_point_y_px(), 6) + ")";
  }
  SamplingSettings sampling = flags.sampling;
  options.sigma = sampling.sigma;
  options.sampling_filter = sampling.filter;
  options.focal_shares_x = parse_focal_shares(flags.focal_shares_x, "--fx");
  options.focal_shares_y = parse_focal_shares(flags.focal_shares_y, "--fy");
  sampling.focal_share_x = options.focal_shares_x.front();
  sampling.focal_share_y = options.focal_shares_y.front();
  for (SamplingModel model : sampling_models) {
    if (model != SamplingModel::rectangular) {
      options.sampling.push_back({parse_sampling(model, sampling, base), sampling_flags_text(model, sampling)});
      continue;
    }
    SamplingSettings pair = sampling;
    for (double focal_share_y : options.focal_shares_y)
      for (double focal_share_x : options.focal_shares_x) {
        pair.focal_share_x = focal_share_x;
        pair.focal_share_y = focal_share_y;
        options.sampling.push_back({parse_sampling(model, pair, base), sampling_flags_text(model, pair)});
      }
  }
  if (!sampling_models.empty()) {
    std::vector<SamplingModel> models;  // each once
    for (SamplingModel model : sampling_models)
      if (std::find(models.begin(), models.end(), model) == models.end()) models.push_back(model);
    options.sampling_flags = all_sampling_flags_text(
        sampling, models,
        "--fx " + exact_numbers_text(options.focal_shares_x) + " --fy " + exact_numbers_text(options.focal_shares_y));
  }
  options.scenes = flags.scenes;
  options.spps = flags.spps;
  options.settings = flags.settings;
  options.pyramid_flags_given = flags.pyramid_flags_given;
  options.repeats = flags.repeats;
  options.json = flags.json;
  options.out_dir = flags.out_dir;
  options.device = flags.device;
  options.require_gpu = flags.require_gpu;
  options.step_breakdown = flags.step_breakdown;
  if (!fipr) return options;

  options.refreshes = parse_refreshes(flags.refresh);
  options.fovea_degs = parse_fovea_degs(flags.fovea_deg);
  options.foveation_flags = foveation_flags_text(flags.foveation);
  if (eye)  // the headset's eye in place of the flat display's flags
    options.foveation_flags =
        options.display_flags + options.foveation_flags.substr(display_flags_text(flags.foveation.display).size());
  for (int refresh : options.refreshes) {
    for (double fovea_deg : options.fovea_degs) {
      FoveationFlags variant_flags = flags.foveation;
      variant_flags.refresh = refresh;
      variant_flags.fovea_deg = fovea_deg;
      bench::FiprVariant variant{refresh, fovea_deg, foveation_of(variant_flags)};
      for (int spp : flags.spps) {
        SphereTraceSettings check = flags.settings;
        check.samples_per_pixel = spp;
        check.method = TraceMethod::foveated_pyramid;
        check.foveation = variant.foveation;
        validate_trace_flags(bench::settings_of(options, check));
      }
      options.variants.push_back(variant);
    }
  }
  return options;
}

}  // namespace

bench::BenchPlan plan_bench(const BenchFlags& flags) { return bench::plan_bench(read_bench_flags(flags)); }

BenchFlags parse_bench_flags(const std::vector<std::string>& words, const std::string& what) {
  BenchFlags flags;
  CLI::App command("fovlab bench", "bench");
  add_bench_flags(command, flags);
  std::vector<std::string> reversed(words.rbegin(), words.rend());  // CLI11 takes them reversed
  try {
    command.parse(reversed);
  } catch (const CLI::ParseError& e) {
    throw InputError(what + ": " + e.what());
  }
  note_given_bench_flags(command, flags);
  return flags;
}

BenchFlags parse_sweep_command(const std::string& command) {
  const std::string start = "fovlab bench ";
  if (command.compare(0, start.size(), start) != 0)
    throw InputError("expected \"fovlab bench\" and the sweep's flags, got " + quoted_input(command));
  return parse_bench_flags(CLI::detail::split_up(command.substr(start.size())), "the sweep's flags");
}

void add_bench_flags(CLI::App& command, BenchFlags& options) {
  command.add_option("--scenes", options.scenes, "Scenes, comma-separated (names or .glsl paths)")->delimiter(',');
  command.add_option("--spp", options.spps, "Samples per pixel, comma-separated (1, 4, 16)")->delimiter(',');
  command.add_option("--width", options.settings.width, "Frame width in pixels");
  command.add_option("--height", options.settings.height, "Frame height in pixels");
  command.add_option("--repeats", options.repeats, "Timed runs per method and cell (median reported)");
  command.add_option("--headset", options.headset,
                     "A headset's study config ([display] kind = \"openxr\"): each eye at its size from its "
                     "head-locked view, FIPR's and the sampling models' eccentricity on its off-axis display");
  command.add_option("--eye", options.eye, "With --headset: left, right or both (a sweep an eye; default both)");
  add_output_option(command, "--json", options.json, "Write the full results as JSON",
                    {{OutputKind::file}, kReplacesAFile});
  add_output_option(command, "--out-dir", options.out_dir,
                    "Write images, step heat maps, FIPR masks, Pareto charts (SVG), table.md and bench.json here",
                    {{OutputKind::folder}, kWritesIntoAFolder});
  command.add_option("--device", options.device, "Vulkan device: index or part of its name (fovlab devices)");
  command.add_flag("--require-gpu", options.require_gpu,
                   "Refuse to run on a CPU Vulkan device (lavapipe): exit 2 on a node without a GPU");
  command.add_option("--over-relax", options.settings.over_relaxation,
                     "IPR's top-level samples step up to this many times the distance bound (Keinert et al. 2014's "
                     "over-relaxation, 1 to 2, each factor adapted to the slope of the last step; a prototype; "
                     "default 1: off). GT stays the plain reference");
  command.add_flag("--step-breakdown", options.step_breakdown,
                   "Count where GT's and IPR's top-level samples spend their steps (one more untimed frame each): "
                   "a table, and \"step_breakdown\" in the JSON");
  command.add_option("--cells", options.cells,
                     "I/N: measure only part I of N of the sweep's (scene, time, spp) units, into --json; fovlab "
                     "bench-merge joins the parts into the sweep's report");
  command
      .add_option("--methods", options.methods,
                  "Methods, comma-separated: gt (always), ipr, fipr, rmfr, hyperbolic, linear, kfr (default gt,ipr)")
      ->delimiter(',');
  add_trace_options(command, options.settings);
  command
      .add_option("--times", options.times,
                  "Scene times in seconds, comma-separated, instead of --time: every scene is measured at each "
                  "(the rotating patterns turn 10 degrees a second)")
      ->delimiter(',');
  // The FIPR flags of `render`, but a list of refresh periods and of foveae: the sweep.
  add_foveation_flags(command, options.foveation, FoveationPoint::swept);
  command.add_option("--refresh", options.refresh, "FIPR: periphery refresh periods, comma-separated (1, 2, 4)")
      ->delimiter(',');
  command
      .add_option("--fovea-deg", options.fovea_deg,
                  "FIPR: foveal eccentricities in degrees, comma-separated (default 2.5,5,7.5,10,12.5,15)")
      ->delimiter(',');
  add_sampling_flags(command, options.sampling, false);
  command
      .add_option("--fx", options.focal_shares_x,
                  "Sampling: rmfr's f_x as shares of the width, comma-separated (with --fy: every pair, Figure 6's "
                  "sweep; default 0.3)")
      ->delimiter(',');
  command.add_option("--fy", options.focal_shares_y, "Sampling: rmfr's f_y as shares of the height, comma-separated")
      ->delimiter(',');
}

void note_given_bench_flags(CLI::App& command, BenchFlags& options) {
  options.fipr_flags_given = given_fipr_only_flags(command);
  options.sampling_flags_given = given_sampling_only_flags(command);
  options.time_given = command.count("--time") > 0;
  options.eye_given = command.count("--eye") > 0;
  options.headset_flags_given.clear();
  for (const char* flag : {"--width", "--height", "--diagonal-in", "--size-mm", "--distance-mm"})
    if (command.count(flag) > 0) options.headset_flags_given.push_back(flag);
  options.pyramid_flags_given = given_pyramid_flags(command);
}

}  // namespace fovlab::app
