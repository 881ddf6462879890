#include "bench/bench_outputs.h"

#include <algorithm>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "bench/bench_pareto.h"
#include "bench/bench_report.h"
#include "core/atomic_file.h"
#include "core/number_text.h"

namespace fovlab::bench {

namespace {

// The fovea of Polychronakis et al. 2023's Table 1 and of its speed-ups "at 7.5 degrees" (section 5.2).
constexpr double kPaperFoveaDeg = 7.5;
const char* const kPaperNote =
    "Polychronakis et al. 2023 at 7.5 degrees: SSIM 0.949-0.990 and FLIP 0.030-0.109 against GT (Table 1); speed-ups "
    "1.1x-16x "
    "(section 5.2).";

// Marks each scene's cells on the Pareto fronts of speed-up against FLIP and against 1 - SSIM
// ("pareto_flip", "pareto_one_minus_ssim").
void mark_pareto_fronts(nlohmann::json& cells, const std::vector<std::string>& scenes) {
  for (const std::string& scene : scenes) {
    for (const char* error : {"flip", "ssim"}) {
      std::vector<TradeOff> points;
      std::vector<nlohmann::json*> of_scene;
      for (nlohmann::json& cell : cells) {
        if (cell["scene"] != scene) continue;
        const double value =
            std::string(error) == "ssim" ? 1.0 - cell["ssim"].get<double>() : cell["flip"].get<double>();
        points.push_back({cell["speedup"].get<double>(), value});
        of_scene.push_back(&cell);
      }
      const std::vector<bool> front = pareto_front(points);
      for (size_t i = 0; i < of_scene.size(); ++i) {
        (*of_scene[i])[std::string(error) == "ssim" ? "pareto_one_minus_ssim" : "pareto_flip"] = bool(front[i]);
      }
    }
  }
}

std::vector<ChartCell> chart_cells(const nlohmann::json& cells, const std::string& scene, bool flip) {
  std::vector<ChartCell> chart;
  for (const nlohmann::json& cell : cells) {
    if (cell["scene"] != scene) continue;
    ChartCell point;
    point.method = cell["method"].get<std::string>();
    point.spp = cell["spp"].get<int>();
    if (point.method == "fipr") {
      point.refresh = cell["refresh"].get<int>();
      point.fovea_deg = cell["fovea_deg"].get<double>();
    }
    if (cell.contains("sampling") && cell["sampling"].contains("shaded_over_reference"))
      point.shaded_over_reference = cell["sampling"]["shaded_over_reference"].get<double>();
    point.trade_off = {cell["speedup"].get<double>(),
                       flip ? cell["flip"].get<double>() : 1.0 - cell["ssim"].get<double>()};
    point.on_front = cell[flip ? "pareto_flip" : "pareto_one_minus_ssim"].get<bool>();
    chart.push_back(point);
  }
  return chart;
}

std::vector<double> numbers(const nlohmann::json& report, const char* axis) {
  if (!report.contains("sampling_focal_shares")) return {};
  return report["sampling_focal_shares"][axis].get<std::vector<double>>();
}

}  // namespace

void print_now(const std::string& text) {
  std::printf("%s", text.c_str());
  std::fflush(stdout);
}

void finish_sweep(nlohmann::json& report, bool rows_printed, const std::filesystem::path& json,
                  const std::filesystem::path& out_dir) {
  nlohmann::json& rows = report["rows"];
  nlohmann::json& cells = report["cells"];
  std::vector<std::string> scene_names;  // in the sweep's order
  bool ipr = false;
  bool sampling = false;
  for (const nlohmann::json& row : rows) {
    const std::string scene = row["scene"].get<std::string>();
    if (std::find(scene_names.begin(), scene_names.end(), scene) == scene_names.end()) scene_names.push_back(scene);
    ipr |= row.contains("ipr");
  }
  for (const nlohmann::json& cell : cells) sampling |= cell.contains("sampling");
  const bool fipr = report.contains("fipr");
  const bool has_cells = fipr || sampling;
  const bool several_times = report["times_s"].size() > 1;
  mark_pareto_fronts(cells, scene_names);

  std::string gt_ipr_table = gt_ipr_table_header();
  for (const nlohmann::json& row : rows) gt_ipr_table += gt_ipr_table_row(row);
  std::string cell_table = cell_table_header();
  for (const nlohmann::json& cell : cells) cell_table += cell_table_row(cell);
  if (!rows_printed) print_now(has_cells ? cell_table : gt_ipr_table);

  const std::string passes = pass_table(rows);
  const std::string fovea_7_5 = fipr ? fovea_table(cells, kPaperFoveaDeg) : "";
  const std::string fronts = pareto_table(cells);
  const std::string models = sampling ? sampling_table(cells) : "";
  const FocalSweep focal_sweep = rmfr_focal_sweep(cells, numbers(report, "x"), numbers(report, "y"));
  const std::string ranking = sampling ? sampling_ranking_table(cells) : "";
  if (has_cells) {
    if (ipr) print_now("\nGT against IPR:\n" + gt_ipr_table);
    if (fipr) print_now("\nFIPR at a fovea of 7.5 degrees:\n" + fovea_7_5 + kPaperNote + "\n");
    if (!models.empty()) print_now("\nSampling models (Ye et al. 2022) against GT:\n" + models);
    if (several_times && !ranking.empty())
      print_now("\nSampling models ranked by mean FPSNR over the scene times:\n" + ranking);
    if (!focal_sweep.table.empty()) print_now("\nRMFR's best f_x, f_y (Figure 6's sweep):\n" + focal_sweep.table);
    print_now("\nPareto fronts (speed-up against error, per scene):\n" + fronts);
  }
  print_now("\nWhere the time goes (median GPU ms per pass):\n" + passes);
  const std::string steps = step_breakdown_table(rows);  // bench --step-breakdown
  if (!steps.empty()) print_now("\nWhere the steps go (the top level's samples; steps per sample, share):\n" + steps);

  // Every file made in memory first, then written: nothing is written if making one fails.
  std::vector<std::pair<std::filesystem::path, std::string>> files;
  const std::string json_text = report.dump(2) + "\n";
  if (!json.empty()) files.emplace_back(json, json_text);
  if (!out_dir.empty()) {
    const int width = report["width"].get<int>();
    const int height = report["height"].get<int>();
    const double flip_pixels_per_degree = report["metrics"]["flip_pixels_per_degree"].get<double>();
    const std::string command = report["command"].get<std::string>();
    files.emplace_back(out_dir / "bench.json", json_text);
    for (const std::string& scene : scene_names) {
      const std::string size = std::to_string(width) + "x" + std::to_string(height);
      files.emplace_back(
          out_dir / (scene + "_pareto_flip.svg"),
          pareto_chart_svg(scene + ", " + size + ": speed-up against FLIP",
                           "FLIP against GT (mean, " + format_number(flip_pixels_per_degree, 3) + " px/deg)",
                           chart_cells(cells, scene, true)));
      files.emplace_back(out_dir / (scene + "_pareto_ssim.svg"),
                         pareto_chart_svg(scene + ", " + size + ": speed-up against 1 - SSIM", "1 - SSIM against GT",
                                          chart_cells(cells, scene, false)));
    }
    const std::string eye = report.contains("eye") ? report["eye"]["name"].get<std::string>() + " eye " : "";
    std::string markdown = "# fovlab bench\n\nCommand: `" + command +
                           "`\n\nDevice: " + report["device"].get<std::string>() + "; " + eye + std::to_string(width) +
                           "x" + std::to_string(height) + "; median of " +
                           std::to_string(report["repeats"].get<int>()) + " runs.\n\n";
    if (ipr || !has_cells) markdown += "## GT against IPR\n\n" + gt_ipr_table + "\n";
    if (has_cells) markdown += "## Every cell\n\n" + cell_table + "\n";
    if (fipr) markdown += "## FIPR at a fovea of 7.5 degrees\n\n" + fovea_7_5 + "\n" + kPaperNote + "\n\n";
    if (!models.empty()) markdown += "## Sampling models (Ye et al. 2022) against GT\n\n" + models + "\n";
    if (several_times && !ranking.empty())
      markdown += "## Sampling models ranked by mean FPSNR over the scene times\n\n" + ranking + "\n";
    if (!focal_sweep.table.empty())
      markdown += "## RMFR's best f_x, f_y (Figure 6's sweep)\n\n" + focal_sweep.table + "\n";
    for (const auto& [file_name, svg] : focal_sweep.heat_maps) files.emplace_back(out_dir / file_name, svg);
    markdown += "## Pareto fronts\n\n" + fronts + "\n## Passes\n\n" + passes;
    if (!steps.empty()) markdown += "\n## Where the steps go\n\n" + steps;
    files.emplace_back(out_dir / "table.md", markdown);
  }
  for (const auto& [path, text] : files) write_text_atomically(path, text);
}

}  // namespace fovlab::bench
