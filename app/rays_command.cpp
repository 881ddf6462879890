// fovlab rays: speed-up of a three-zone foveated frame over a grid of foveal and middle zone
// angles (Polychronakis et al. 2021, section 5.1 and Table 1; docs/analysis.md, "Ray reduction").
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/rays/ray_count.h"
#include "analysis/report/svg_chart.h"
#include "app/commands.h"
#include "app/display_flags.h"
#include "app/output_options.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "foveation/display_geometry.h"

namespace fovlab::app {

namespace {

// The eccentricity table holds one double a pixel: 8K UHD (7680x4320) is the largest frame taken.
constexpr int64_t kMaxPixels = int64_t{1} << 25;

struct RaysOptions {
  std::string resolution;
  DisplayFlags display;
  std::string foveal_deg;
  std::string middle_deg;
  std::filesystem::path json;
  std::filesystem::path svg;
};

std::optional<int> parse_int(std::string_view text) {
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::pair<int, int> parse_resolution(const std::string& text) {
  const std::string expected = "WxH in pixels, two positive whole numbers (e.g. 1920x1080)";
  const auto parts = split_pair(text, "xX");
  if (!parts) fail_flag("--resolution", expected, text);
  const std::optional<int> width = parse_int(parts->first);
  const std::optional<int> height = parse_int(parts->second);
  if (!width || !height || *width <= 0 || *height <= 0) fail_flag("--resolution", expected, text);
  if (int64_t{*width} * *height > kMaxPixels) {
    fail_flag("--resolution", "at most " + std::to_string(kMaxPixels) + " pixels (8K UHD, 7680x4320, fits)", text);
  }
  return {*width, *height};
}

std::vector<double> parse_angles(const std::string& flag, const std::string& text) {
  const std::string expected = "comma-separated angles in degrees, each a number >= 0 (e.g. 5,10,15)";
  std::vector<double> angles;
  std::string_view rest = text;
  while (true) {
    const size_t comma = rest.find(',');
    const std::optional<double> angle = parse_finite_number(rest.substr(0, comma));
    if (!angle || *angle < 0.0) fail_flag(flag, expected, text);
    angles.push_back(*angle == 0.0 ? 0.0 : *angle);  // -0 reads as 0
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return angles;
}

// "4.99x": the speed-up rounded to two decimals.
std::string speedup_text(double speedup) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2fx", speedup);
  return text;
}

void print_table(const DisplayGeometry& display, double gaze_x, double gaze_y, const std::vector<double>& foveal,
                 const std::vector<double>& middle, const std::vector<analysis::RayCell>& cells) {
  std::printf("display %dx%d px, %s x %s mm, viewed from %s mm (%.1f px/deg at the centre)\n", display.width_px,
              display.height_px, format_number(display.width_mm, 5).c_str(),
              format_number(display.height_mm, 5).c_str(), format_number(display.viewing_distance_mm, 6).c_str(),
              display.pixels_per_degree_at_centre());
  std::printf("gaze (%s, %s) px\n", format_number(gaze_x, 6).c_str(), format_number(gaze_y, 6).c_str());
  std::printf("full frame: %lld rays (one a pixel); foveated: foveal 1 a pixel, middle 1 per 4, outer 1 per 16\n",
              static_cast<long long>(display.width_px) * display.height_px);
  std::printf("speed-up (rows: foveal zone, columns: middle zone; full apertures in degrees)\n");
  // Column width: the widest of the header labels and the cells.
  size_t width = 6;
  for (double m : middle) width = std::max(width, format_number(m, 6).size());
  for (const analysis::RayCell& cell : cells) width = std::max(width, speedup_text(cell.speedup).size());
  size_t label_width = std::string("foveal\\middle").size();
  for (double f : foveal) label_width = std::max(label_width, format_number(f, 6).size());
  std::printf("%-*s", static_cast<int>(label_width), "foveal\\middle");
  for (double m : middle) std::printf("  %*s", static_cast<int>(width), format_number(m, 6).c_str());
  std::printf("\n");
  for (size_t row = 0; row < foveal.size(); ++row) {
    std::printf("%-*s", static_cast<int>(label_width), format_number(foveal[row], 6).c_str());
    for (size_t column = 0; column < middle.size(); ++column) {
      std::printf("  %*s", static_cast<int>(width), speedup_text(cells[row * middle.size() + column].speedup).c_str());
    }
    std::printf("\n");
  }
}

nlohmann::json cells_json(const std::vector<analysis::RayCell>& cells) {
  nlohmann::json out = nlohmann::json::array();
  for (const analysis::RayCell& cell : cells) {
    out.push_back({{"foveal_deg", cell.foveal_deg},
                   {"middle_deg", cell.middle_deg},
                   {"rays", cell.rays},
                   {"speedup", cell.speedup},
                   {"foveal_pixels", cell.foveal_pixels},
                   {"middle_pixels", cell.middle_pixels},
                   {"outer_pixels", cell.outer_pixels}});
  }
  return out;
}

void run_rays(const RaysOptions& options) {
  // Every flag is checked before the table is built.
  const auto [width_px, height_px] = parse_resolution(options.resolution);
  const DisplayGeometry display = parse_display(options.display, width_px, height_px);
  const std::vector<double> foveal = parse_angles("--foveal-deg", options.foveal_deg);
  const std::vector<double> middle = parse_angles("--middle-deg", options.middle_deg);
  const auto [gaze_x, gaze_y] = parse_gaze(options.display.gaze, width_px, height_px);

  const std::vector<analysis::RayCell> cells = analysis::count_ray_grid(display, gaze_x, gaze_y, foveal, middle);
  print_table(display, gaze_x, gaze_y, foveal, middle, cells);
  if (!options.json.empty()) {
    write_text_atomically(options.json, cells_json(cells).dump(2) + "\n");
    std::printf("wrote %s\n", options.json.c_str());
  }
  if (!options.svg.empty()) {  // Polychronakis et al. 2021 Fig. 8, as a heat map of the speed-up
    analysis::HeatMap map;
    map.title = "Speed-up from ray reduction (" + std::to_string(width_px) + "x" + std::to_string(height_px) + ", " +
                format_number(display.viewing_distance_mm, 6) + " mm)";
    map.x_label = "middle zone (deg)";
    map.y_label = "foveal zone (deg)";
    map.x_values = middle;
    map.y_values = foveal;
    for (const analysis::RayCell& cell : cells) map.cells.push_back(cell.speedup);
    write_text_atomically(options.svg, analysis::render_heat_map_svg(map));
    std::printf("wrote %s\n", options.svg.c_str());
  }
}

}  // namespace

void add_rays_command(CLI::App& app) {
  auto options = std::make_shared<RaysOptions>();
  CLI::App* command = app.add_subcommand(
      "rays", "Ray-count speed-up of a three-zone foveated frame (Polychronakis et al. 2021, Table 1)");
  command->add_option("--resolution", options->resolution, "Display resolution WxH in pixels, e.g. 1920x1080")
      ->required();
  add_display_flags(*command, options->display, /*required=*/true);
  command->add_option("--foveal-deg", options->foveal_deg, "Foveal zone angles, full aperture in degrees, e.g. 5,10,15")
      ->required();
  command->add_option("--middle-deg", options->middle_deg, "Middle zone angles, full aperture in degrees, e.g. 50,60")
      ->required();
  add_output_option(*command, "--json", options->json, "Also write the cells as JSON to this file",
                    {{OutputKind::file}, kReplacesAFile});
  add_output_option(*command, "--svg", options->svg, "Also draw the speed-ups as a heat map (SVG) to this file",
                    {{OutputKind::file}, kReplacesAFile});
  command->callback([options] { run_rays(*options); });
}

}  // namespace fovlab::app
