#include "app/bench_plan.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <sstream>

#include "app/cli_support.h"
#include "app/display_flags.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "renderer/scene/scene_source.h"

namespace fovlab::app {

namespace {

constexpr int kMinSsimSidePx = 11;  // SSIM's 11x11 window must fit in the frame

template <typename T>
std::string join(const std::vector<T>& values) {
  std::ostringstream out;
  for (size_t i = 0; i < values.size(); ++i) out << (i ? "," : "") << values[i];
  return out.str();
}

// As given: a merge rebuilds the sweep's cells from its command (exact_number_text reads back the same).
std::string join_numbers(const std::vector<double>& values) {
  std::string text;
  for (size_t i = 0; i < values.size(); ++i) text += (i ? "," : "") + exact_number_text(values[i]);
  return text;
}

template <typename T>
void refuse_repeats(const std::vector<T>& values, const std::string& flag, const std::string& text) {
  for (size_t i = 0; i < values.size(); ++i) {
    if (std::find(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), values[i]) !=
        values.begin() + static_cast<std::ptrdiff_t>(i)) {
      fail_flag(flag, "each value once", text);
    }
  }
}

struct Methods {
  bool ipr = false;
  bool fipr = false;
  std::vector<SamplingModel> sampling_models;  // in the order given
};

Methods parse_methods(const std::vector<std::string>& names) {
  const std::string text = join(names);
  const std::string expected =
      "a comma-separated list of gt, ipr, fipr, rmfr, hyperbolic, linear and kfr that includes gt (the reference)";
  Methods methods;
  for (const std::string& name : names) {
    if (const std::optional<SamplingModel> model = parse_sampling_model(name)) methods.sampling_models.push_back(*model);
    else if (name != "gt" && name != "ipr" && name != "fipr") fail_flag("--methods", expected, text);
  }
  refuse_repeats(names, "--methods", text);
  if (std::find(names.begin(), names.end(), "gt") == names.end()) fail_flag("--methods", expected, text);
  methods.ipr = std::find(names.begin(), names.end(), "ipr") != names.end();
  methods.fipr = std::find(names.begin(), names.end(), "fipr") != names.end();
  return methods;
}

// The sampling models of a plan, in order, each once (RMFR's several maps, a focal sweep, are one).
std::vector<SamplingModel> sampling_models(const BenchPlan& plan) {
  std::vector<SamplingModel> models;
  for (const SamplingMap& map : plan.sampling_maps)
    if (std::find(models.begin(), models.end(), model_of(map)) == models.end()) models.push_back(model_of(map));
  return models;
}

// "gt,ipr,fipr,rmfr,...": the methods of a plan, as --methods takes them.
std::string methods_text(const BenchPlan& plan, bool with_ipr, bool with_fipr) {
  std::string text = with_ipr ? "gt,ipr" : "gt";
  if (with_fipr) text += ",fipr";
  for (SamplingModel model : sampling_models(plan)) text += std::string(",") + sampling_model_name(model);
  return text;
}

std::vector<int> parse_refreshes(const std::vector<std::string>& texts) {
  const std::string text = join(texts);
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
  const std::string text = join(texts);
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
  const std::string text = join(texts);
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
  const std::string text = join(texts);
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

std::string time_flag(float time_s) { return "--time " + exact_number_text(time_s); }

// A word of a command as a shell (and CLI11's split_up) reads it back: quoted when it holds a space.
std::string command_word(const std::string& word) {
  if (word.find_first_of(" \t") == std::string::npos) return word;
  return word.find('\'') == std::string::npos ? "'" + word + "'" : "\"" + word + "\"";
}

// `time_text`: "--time T" or "--times A,B,...".
std::string command_text(const BenchOptions& options, const std::string& scenes, const std::string& spps,
                         const std::string& methods, const std::string& time_text) {
  const SphereTraceSettings& s = options.settings;
  std::ostringstream out;
  out << "fovlab bench --scenes " << command_word(scenes) << " --spp " << spps << " --width " << s.width << " --height " << s.height
      << " --repeats " << options.repeats << " " << time_text << " --levels " << s.pyramid_levels
      << " --min-filter " << s.min_filter_size << " --coarse-test " << coarse_test_name(s.coarse_test)
      << (s.full_resolution_depth ? " --full-depth" : "") << " --max-steps " << s.max_steps << " --hit-threshold "
      << exact_number_text(s.hit_threshold) << " --methods " << methods;
  return out.str();
}

}  // namespace


BenchPlan plan_bench(const BenchOptions& options) {
  std::optional<SweepPart> part;
  if (!options.cells.empty()) {
    const PartOfN given = parse_part_of_n(options.cells, "--cells", "e.g. 1/4: units 1, 5, 9, ... of the sweep");
    part = SweepPart{given.index, given.count};
    if (options.json.empty())
      throw InputError("--cells " + options.cells + ": needs --json PART.json (fovlab bench-merge joins the parts)");
    if (!options.out_dir.empty())
      throw InputError("--out-dir: not with --cells (a part's tables and charts are not the sweep's); give --out-dir "
                       "to fovlab bench-merge");
  }
  if (options.repeats < 1 || options.repeats > 1000) {
    throw InputError("--repeats " + std::to_string(options.repeats) + ": expected 1 to 1000");
  }
  const Methods methods = parse_methods(options.methods);
  if (!methods.fipr && !options.fipr_flags_given.empty()) {
    throw InputError(options.fipr_flags_given.front() + ": only FIPR uses it; add fipr to --methods (e.g. gt,ipr,fipr)");
  }
  if (methods.sampling_models.empty() && !options.sampling_flags_given.empty()) {
    throw InputError(options.sampling_flags_given.front() +
                     ": only the sampling models use it; add rmfr, hyperbolic, linear or kfr to --methods");
  }
  refuse_flags_unused_by(options.sampling_flags_given, methods.sampling_models);
  const int width = options.settings.width;
  const int height = options.settings.height;
  for (int spp : options.spps) {
    SphereTraceSettings check = options.settings;
    check.samples_per_pixel = spp;
    validate_trace_flags(check);
  }
  if (width < kMinSsimSidePx || height < kMinSsimSidePx) {
    throw InputError("--width " + std::to_string(width) + " --height " + std::to_string(height) +
                     ": expected at least 11x11 pixels (the SSIM window)");
  }
  if (options.foveation.display.gaze == "none") {
    fail_flag("--gaze", "a gaze point X,Y (FPSNR and FIPR's mask need one; left out: the centre)", "none");
  }

  BenchPlan plan;
  plan.part = part;
  plan.ipr = methods.ipr;
  plan.fipr = methods.fipr;
  if (!options.times.empty() && options.time_given) {
    throw InputError("--time, --times: expected one of them (one scene time, or a comma-separated list)");
  }
  plan.times_s = options.times.empty() ? std::vector<float>{options.settings.time_s} : parse_times(options.times);
  const FoveationSettings base = parse_foveation(options.foveation, width, height);
  plan.display = base.display;
  plan.gaze_x_px = base.gaze_x_px;
  plan.gaze_y_px = base.gaze_y_px;
  plan.flip_pixels_per_degree = plan.display.pixels_per_degree_at_centre();
  plan.sampling = options.sampling;
  plan.focal_shares_x = parse_focal_shares(options.focal_shares_x, "--fx");
  plan.focal_shares_y = parse_focal_shares(options.focal_shares_y, "--fy");
  plan.sampling.focal_share_x = plan.focal_shares_x.front();
  plan.sampling.focal_share_y = plan.focal_shares_y.front();
  for (SamplingModel model : methods.sampling_models) {
    if (model != SamplingModel::rectangular) {
      plan.sampling_maps.push_back(parse_sampling(model, plan.sampling, base));
      continue;
    }
    SamplingSettings pair = plan.sampling;
    for (double focal_share_y : plan.focal_shares_y)
      for (double focal_share_x : plan.focal_shares_x) {
        pair.focal_share_x = focal_share_x;
        pair.focal_share_y = focal_share_y;
        plan.sampling_maps.push_back(parse_sampling(model, pair, base));
      }
  }
  if (!plan.fipr) return plan;

  plan.refreshes = parse_refreshes(options.refresh);
  plan.fovea_degs = parse_fovea_degs(options.fovea_deg);
  for (int refresh : plan.refreshes) {
    for (double fovea_deg : plan.fovea_degs) {
      FoveationFlags flags = options.foveation;
      flags.refresh = refresh;
      flags.fovea_deg = fovea_deg;
      FiprVariant variant{refresh, fovea_deg, parse_foveation(flags, width, height)};
      for (int spp : options.spps) {
        SphereTraceSettings check = options.settings;
        check.samples_per_pixel = spp;
        check.method = TraceMethod::foveated_pyramid;
        check.foveation = variant.foveation;
        validate_trace_flags(check);
      }
      plan.variants.push_back(variant);
    }
  }
  return plan;
}

std::string sweep_command(const BenchOptions& options, const BenchPlan& plan) {
  std::string times;
  for (size_t i = 0; i < plan.times_s.size(); ++i) times += (i ? "," : "") + exact_number_text(plan.times_s[i]);
  const std::string time_text = options.times.empty() ? time_flag(options.settings.time_s) : "--times " + times;
  std::string text = command_text(options, join(options.scenes), join(options.spps),
                                  methods_text(plan, plan.ipr, plan.fipr), time_text);
  if (!plan.sampling_maps.empty())
    text += " " + all_sampling_flags_text(plan.sampling, sampling_models(plan),
                                          "--fx " + join_numbers(plan.focal_shares_x) + " --fy " +
                                              join_numbers(plan.focal_shares_y));
  if (!plan.fipr) return text + " " + display_flags_text(options.foveation.display);
  return text + " --refresh " + join(plan.refreshes) + " --fovea-deg " + join_numbers(plan.fovea_degs) + " " +
         foveation_flags_text(options.foveation);
}

std::string cell_command(const BenchOptions& options, const BenchPlan& plan, const std::string& scene, float time_s,
                         int spp, const std::string& method, const FiprVariant* variant, const SamplingMap* map) {
  const std::string time_text = time_flag(time_s);
  if (const std::optional<SamplingModel> model = parse_sampling_model(method)) {
    SamplingSettings settings = plan.sampling;
    if (const auto* rmfr = map ? std::get_if<RectangularMapping>(map) : nullptr) {
      settings.focal_share_x = rmfr->x.focal_share;
      settings.focal_share_y = rmfr->y.focal_share;
    }
    return command_text(options, scene, std::to_string(spp), "gt," + method, time_text) + " " +
           sampling_flags_text(*model, settings) + " " + display_flags_text(options.foveation.display);
  }
  if (method != "fipr" || !variant) {
    return command_text(options, scene, std::to_string(spp), plan.ipr ? "gt,ipr" : "gt", time_text) +
           " " + display_flags_text(options.foveation.display);
  }
  return command_text(options, scene, std::to_string(spp), "gt,fipr", time_text) + " --refresh " +
         std::to_string(variant->refresh) + " --fovea-deg " + exact_number_text(variant->fovea_deg) + " " +
         foveation_flags_text(options.foveation);
}

BenchOptions parse_bench_flags(const std::vector<std::string>& words, const std::string& what) {
  BenchOptions options;
  CLI::App command("fovlab bench", "bench");
  add_bench_flags(command, options);
  std::vector<std::string> reversed(words.rbegin(), words.rend());  // CLI11 takes them reversed
  try {
    command.parse(reversed);
  } catch (const CLI::ParseError& e) {
    throw InputError(what + ": " + e.what());
  }
  note_given_bench_flags(command, options);
  return options;
}

BenchOptions parse_sweep_command(const std::string& command) {
  const std::string start = "fovlab bench ";
  if (command.compare(0, start.size(), start) != 0)
    throw InputError("expected \"fovlab bench\" and the sweep's flags, got " + quoted_input(command));
  return parse_bench_flags(CLI::detail::split_up(command.substr(start.size())), "the sweep's flags");
}

bench::SweepLayout sweep_layout(const BenchOptions& options, const BenchPlan& plan) {
  bench::SweepLayout layout;
  for (const std::string& scene : options.scenes) layout.scenes.push_back(scene_name(scene));
  layout.times_s = plan.times_s;
  layout.spps = options.spps;
  layout.width = options.settings.width;
  layout.height = options.settings.height;
  layout.repeats = options.repeats;
  // As run_bench measures a unit: GT, IPR, every FIPR variant, every sampling model's map.
  layout.unit_cells.push_back({"gt"});
  if (plan.ipr) layout.unit_cells.push_back({"ipr"});
  for (const FiprVariant& variant : plan.variants)
    layout.unit_cells.push_back({"fipr", variant.refresh, variant.fovea_deg, std::nullopt, std::nullopt});
  if (!plan.sampling_maps.empty()) {
    layout.focal_shares_x = plan.focal_shares_x;
    layout.focal_shares_y = plan.focal_shares_y;
  }
  for (const SamplingMap& map : plan.sampling_maps) {
    bench::PlannedCell cell{sampling_model_name(model_of(map))};
    if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) {
      cell.focal_share_x = rmfr->x.focal_share;
      cell.focal_share_y = rmfr->y.focal_share;
    }
    layout.unit_cells.push_back(cell);
  }
  return layout;
}

}  // namespace fovlab::app
