#include "bench/bench_report.h"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <vector>

#include "analysis/report/svg_chart.h"
#include "core/number_text.h"
#include "renderer/sphere_tracing/step_breakdown.h"

namespace fovlab::bench {

namespace {

std::string number(const nlohmann::json& value, const char* format) {
  if (value.is_null()) return "inf";  // PSNR and FPSNR of identical frames
  char text[64];
  std::snprintf(text, sizeof(text), format, value.get<double>());
  return text;
}

std::string percent(const nlohmann::json& share) {
  return share.is_number() ? number(100.0 * share.get<double>(), "%.1f%%") : "-";
}

std::string cell_settings_label(const nlohmann::json& cell) {
  const std::string method = cell["method"].get<std::string>();
  if (method != "fipr") return method + " " + std::to_string(cell["spp"].get<int>());
  return std::to_string(cell["spp"].get<int>()) + "/" + std::to_string(cell["refresh"].get<int>()) + "/" +
         format_number(cell["fovea_deg"].get<double>(), 6);
}

}  // namespace

std::string gt_ipr_table_header() {
  return "| scene | spp | GT ms | IPR ms | speed-up | floor ms | GT/floor | IPR/floor | GT steps/px | IPR steps/px | "
         "SSIM | PSNR dB | FLIP | FPSNR dB | capped GT/IPR |\n"
         "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
}

std::string gt_ipr_table_row(const nlohmann::json& row) {
  const nlohmann::json& gt = row["gt"];
  std::ostringstream out;
  const double floor_ms = row["floor"]["median_gpu_ms"].get<double>();
  const auto over_floor = [&](const nlohmann::json& runs) {
    return number(runs["median_gpu_ms"].get<double>() / floor_ms, "%.2fx");
  };
  out << "| " << row["scene"].get<std::string>() << " | " << row["spp"].get<int>() << " | "
      << number(gt["median_gpu_ms"], "%.1f") << " | ";
  if (!row.contains("ipr")) {
    out << "- | - | " << number(floor_ms, "%.1f") << " | " << over_floor(gt) << " | - | "
        << number(gt["steps_per_pixel"], "%.1f") << " | - | - | - | - | - | "
        << gt["capped_rays"].get<unsigned long long>() << "/- |\n";
    return out.str();
  }
  const nlohmann::json& ipr = row["ipr"];
  out << number(ipr["median_gpu_ms"], "%.1f") << " | " << number(row["speedup"], "%.2fx") << " | "
      << number(floor_ms, "%.1f") << " | " << over_floor(gt) << " | " << over_floor(ipr) << " | "
      << number(gt["steps_per_pixel"], "%.1f") << " | " << number(ipr["steps_per_pixel"], "%.1f") << " | "
      << number(row["ssim"], "%.5f") << " | " << number(row["psnr_db"], "%.2f") << " | " << number(row["flip"], "%.5f")
      << " | " << number(row["fpsnr_db"], "%.2f") << " | " << gt["capped_rays"].get<unsigned long long>() << "/"
      << ipr["capped_rays"].get<unsigned long long>() << " |\n";
  return out.str();
}

std::string pass_table(const nlohmann::json& rows) {
  std::ostringstream out;
  out << "| scene | spp | method | pass | median GPU ms | share |\n|---|---:|---|---|---:|---:|\n";
  for (const nlohmann::json& row : rows) {
    for (const char* method : {"gt", "ipr", "floor"}) {
      if (!row.contains(method)) continue;
      const nlohmann::json& runs = row[method];
      const double total = runs["median_gpu_ms"].get<double>();
      for (const auto& [name, ms] : runs["median_pass_gpu_ms"].items()) {
        char text[256];
        std::snprintf(text, sizeof(text), "| %s | %d | %s | %s | %.2f | %.0f%% |\n",
                      row["scene"].get<std::string>().c_str(), row["spp"].get<int>(), method, name.c_str(),
                      ms.get<double>(), total > 0 ? 100.0 * ms.get<double>() / total : 0.0);
        out << text;
      }
    }
  }
  return out.str();
}

std::string step_breakdown_table(const nlohmann::json& rows) {
  std::ostringstream out;
  bool any = false;
  for (const nlohmann::json& row : rows) {
    for (const char* method : {"gt", "ipr"}) {
      if (!row.contains(method) || !row[method].contains("step_breakdown")) continue;
      if (!any) {
        out << "| scene | spp | method | steps/sample |";
        for (int c = 0; c < kStepCategoryCount; ++c) out << " " << step_category_name(c) << " |";
        out << " one-surface px | shared approach |\n|---|---:|---|---:|";
        for (int c = 0; c < kStepCategoryCount; ++c) out << "---:|";
        out << "---:|---:|\n";
        any = true;
      }
      const nlohmann::json& breakdown = row[method]["step_breakdown"];
      out << "| " << row["scene"].get<std::string>() << " | " << row["spp"].get<int>() << " | " << method << " | "
          << number(breakdown["steps_per_sample"], "%.2f") << " |";
      for (int c = 0; c < kStepCategoryCount; ++c) {
        const nlohmann::json& category = breakdown["categories"][step_category_name(c)];
        out << " " << number(category["steps_per_sample"], "%.2f") << " (" << percent(category["share"]) << ") |";
      }
      out << " " << percent(breakdown["one_surface"]["share"]) << " | "
          << percent(breakdown["one_surface"]["shared_approach_share"]) << " |\n";
    }
  }
  return any ? out.str() : std::string();
}

std::string cell_table_header() {
  return "| scene | time s | spp | method | refresh | fovea deg | GPU ms | speed-up | steps/px | top level | refreshed "
         "| "
         "SSIM | FLIP | FPSNR dB |\n"
         "|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
}

std::string cell_table_row(const nlohmann::json& cell) {
  const bool fipr = cell["method"] == "fipr";
  std::ostringstream out;
  out << "| " << cell["scene"].get<std::string>() << " | " << number(cell["time_s"], "%g") << " | "
      << cell["spp"].get<int>() << " | " << cell["method"].get<std::string>() << " | "
      << (fipr ? std::to_string(cell["refresh"].get<int>()) : "-") << " | "
      << (fipr ? format_number(cell["fovea_deg"].get<double>(), 6) : "-") << " | "
      << number(cell["median_gpu_ms"], "%.1f") << " | " << number(cell["speedup"], "%.2fx") << " | "
      << number(cell["steps_per_pixel"], "%.1f") << " | " << percent(cell["top_level_share"]) << " | "
      << percent(cell["refreshed_share"]) << " | " << number(cell["ssim"], "%.5f") << " | "
      << number(cell["flip"], "%.5f") << " | " << number(cell["fpsnr_db"], "%.2f") << " |\n";
  return out.str();
}

namespace {
// "kfr", or RMFR with its focal shares ("rmfr 0.3/0.3"), so a focal sweep's cells stay apart.
std::string model_label(const nlohmann::json& cell) {
  std::string label = cell["method"].get<std::string>();
  if (cell.contains("focal_share_x"))
    label += " " + format_number(cell["focal_share_x"].get<double>(), 6) + "/" +
             format_number(cell["focal_share_y"].get<double>(), 6);
  return label;
}
}  // namespace

std::string sampling_table(const nlohmann::json& cells) {
  std::ostringstream out;
  out << "| scene | time s | spp | model (rmfr: f_x/f_y) | GPU ms | GT ms | speed-up | theoretical | effective | "
         "shaded | samples / rmfr's | PSNR dB | SSIM | "
         "FLIP | FPSNR dB |\n|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const nlohmann::json& cell : cells) {
    if (!cell.contains("sampling")) continue;
    const nlohmann::json& sampling = cell["sampling"];
    out << "| " << cell["scene"].get<std::string>() << " | " << number(cell["time_s"], "%g") << " | "
        << cell["spp"].get<int>() << " | " << model_label(cell) << " | " << number(cell["median_gpu_ms"], "%.1f")
        << " | " << number(cell["gt_median_gpu_ms"], "%.1f") << " | " << number(cell["speedup"], "%.2fx") << " | "
        << number(sampling["theoretical_speedup"], "%.2fx") << " | " << number(sampling["effective_speedup"], "%.2fx")
        << " | " << percent(sampling["shaded_share"]) << " | "
        << (sampling.contains("shaded_over_reference") ? number(sampling["shaded_over_reference"], "%.3f") : "-")
        << " | " << number(cell["psnr_db"], "%.2f") << " | " << number(cell["ssim"], "%.5f") << " | " << number(cell["flip"], "%.5f") << " | "
        << number(cell["fpsnr_db"], "%.2f") << " |\n";
  }
  return out.str();
}

std::string sampling_ranking_table(const nlohmann::json& cells) {
  struct Summary {
    std::vector<double> fpsnr, psnr, ssim, speedup;
  };
  // (scene, spp) -> model -> its cells' values, in the cells' order.
  std::map<std::pair<std::string, int>, std::map<std::string, Summary>> groups;
  for (const nlohmann::json& cell : cells) {
    if (!cell.contains("sampling") || !cell["fpsnr_db"].is_number() || !cell["psnr_db"].is_number()) continue;
    Summary& summary = groups[{cell["scene"].get<std::string>(), cell["spp"].get<int>()}][model_label(cell)];
    summary.fpsnr.push_back(cell["fpsnr_db"].get<double>());
    summary.psnr.push_back(cell["psnr_db"].get<double>());
    summary.ssim.push_back(cell["ssim"].get<double>());
    summary.speedup.push_back(cell["speedup"].get<double>());
  }
  const auto mean = [](const std::vector<double>& values) {
    double sum = 0.0;
    for (double value : values) sum += value;
    return sum / double(values.size());
  };
  const auto median = [](std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t middle = values.size() / 2;
    return values.size() % 2 ? values[middle] : 0.5 * (values[middle - 1] + values[middle]);
  };
  std::ostringstream out;
  out << "| scene | spp | rank | model (rmfr: f_x/f_y) | times | mean FPSNR dB | mean PSNR dB | mean SSIM | median "
         "speed-up |\n"
         "|---|---:|---:|---|---:|---:|---:|---:|---:|\n";
  for (const auto& [key, models] : groups) {
    std::vector<std::pair<double, std::string>> order;
    for (const auto& [model, summary] : models) order.emplace_back(-mean(summary.fpsnr), model);
    std::sort(order.begin(), order.end());
    int rank = 0;
    for (const auto& [negative_fpsnr, model] : order) {
      const Summary& summary = models.at(model);
      char line[256];
      std::snprintf(line, sizeof(line), "| %s | %d | %d | %s | %zu | %.2f | %.2f | %.4f | %.2fx |\n", key.first.c_str(),
                    key.second, ++rank, model.c_str(), summary.fpsnr.size(), -negative_fpsnr, mean(summary.psnr),
                    mean(summary.ssim), median(summary.speedup));
      out << line;
    }
  }
  return out.str();
}

FocalSweep rmfr_focal_sweep(const nlohmann::json& cells, const std::vector<double>& focal_shares_x,
                            const std::vector<double>& focal_shares_y) {
  FocalSweep sweep;
  if (focal_shares_x.size() * focal_shares_y.size() < 2) return sweep;
  // (scene, time, spp) -> the grid's cells, row-major over (f_y, f_x) as the heat map takes them.
  std::map<std::tuple<std::string, double, int>, std::vector<const nlohmann::json*>> groups;
  for (const nlohmann::json& cell : cells) {
    if (cell["method"] != "rmfr" || !cell.contains("focal_share_x")) continue;
    auto& grid = groups[{cell["scene"].get<std::string>(), cell["time_s"].get<double>(), cell["spp"].get<int>()}];
    grid.resize(focal_shares_x.size() * focal_shares_y.size(), nullptr);
    const auto column = std::find(focal_shares_x.begin(), focal_shares_x.end(), cell["focal_share_x"].get<double>());
    const auto row = std::find(focal_shares_y.begin(), focal_shares_y.end(), cell["focal_share_y"].get<double>());
    if (column == focal_shares_x.end() || row == focal_shares_y.end()) continue;
    grid[size_t(row - focal_shares_y.begin()) * focal_shares_x.size() + size_t(column - focal_shares_x.begin())] =
        &cell;
  }
  std::ostringstream table;
  table << "| scene | time s | spp | metric | best f_x | best f_y | value | worst "
           "|\n|---|---:|---:|---|---:|---:|---:|---:|\n";
  const struct {
    const char* key;
    const char* name;
    const char* format;
  } metrics[] = {{"fpsnr_db", "FPSNR dB", "%.2f"}, {"psnr_db", "PSNR dB", "%.2f"}, {"ssim", "SSIM", "%.4f"}};
  for (const auto& [key, grid] : groups) {
    const auto& [scene, time_s, spp] = key;
    for (const auto& metric : metrics) {
      analysis::HeatMap map;
      map.x_label = "f_x (share of the width)";
      map.y_label = "f_y (share of the height)";
      map.x_values = focal_shares_x;
      map.y_values = focal_shares_y;
      map.cell_format = metric.format;
      size_t best = 0;
      double worst = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < grid.size(); ++i) {
        const nlohmann::json* cell = grid[i];
        const double value = cell && (*cell)[metric.key].is_number() ? (*cell)[metric.key].get<double>()
                                                                     : std::numeric_limits<double>::quiet_NaN();
        map.cells.push_back(value);
        if (std::isfinite(value) && (!std::isfinite(map.cells[best]) || value > map.cells[best])) best = i;
        if (std::isfinite(value)) worst = std::min(worst, value);
      }
      if (!std::isfinite(map.cells[best])) continue;
      map.marked_cells = {best};
      map.marked_label = "outlined: best";
      char time_text[32];
      std::snprintf(time_text, sizeof(time_text), "%g", time_s);
      map.title = "RMFR " + std::string(metric.name) + ", " + scene + " at " + time_text + " s, " +
                  std::to_string(spp) + " spp";
      const std::string metric_key = metric.key;
      sweep.heat_maps.emplace_back(scene + "_t" + time_text + "_spp" + std::to_string(spp) + "_rmfr_" +
                                       metric_key.substr(0, metric_key.find('_')) + ".svg",
                                   analysis::render_heat_map_svg(map));
      char line[256];
      std::snprintf(line, sizeof(line), "| %s | %s | %d | %s | %g | %g | ", scene.c_str(), time_text, spp, metric.name,
                    focal_shares_x[best % focal_shares_x.size()], focal_shares_y[best / focal_shares_x.size()]);
      table << line << number(map.cells[best], metric.format) << " | " << number(worst, metric.format) << " |\n";
    }
  }
  sweep.table = table.str();
  return sweep;
}

std::string fovea_table(const nlohmann::json& cells, double fovea_deg) {
  std::ostringstream out;
  out << "| scene | spp | refresh | FIPR ms | GT ms | speed-up | SSIM | FLIP "
         "|\n|---|---:|---:|---:|---:|---:|---:|---:|\n";
  int count = 0;
  for (const nlohmann::json& cell : cells) {
    if (cell["method"] != "fipr" || cell["fovea_deg"].get<double>() != fovea_deg) continue;
    ++count;
    out << "| " << cell["scene"].get<std::string>() << " | " << cell["spp"].get<int>() << " | "
        << cell["refresh"].get<int>() << " | " << number(cell["median_gpu_ms"], "%.1f") << " | "
        << number(cell["gt_median_gpu_ms"], "%.1f") << " | " << number(cell["speedup"], "%.2fx") << " | "
        << number(cell["ssim"], "%.5f") << " | " << number(cell["flip"], "%.5f") << " |\n";
  }
  if (count == 0) return "No FIPR cell has a fovea of " + format_number(fovea_deg, 6) + " degrees (--fovea-deg).\n";
  return out.str();
}

std::string pareto_table(const nlohmann::json& cells) {
  std::vector<std::string> scenes;
  for (const nlohmann::json& cell : cells) {
    const std::string scene = cell["scene"].get<std::string>();
    if (scenes.empty() || scenes.back() != scene) scenes.push_back(scene);
  }
  std::ostringstream out;
  out << "| scene | error | on the Pareto front, by speed-up (speed-up, error; FIPR as spp/refresh/fovea deg) |\n"
         "|---|---|---|\n";
  for (const std::string& scene : scenes) {
    for (const auto& [key, error, name] :
         {std::tuple{"pareto_flip", "flip", "FLIP"}, std::tuple{"pareto_one_minus_ssim", "ssim", "1 - SSIM"}}) {
      std::vector<std::tuple<double, double, std::string>> front;  // speed-up, error, settings
      for (const nlohmann::json& cell : cells) {
        if (cell["scene"] != scene || !cell.value(key, false)) continue;
        const double value =
            std::string(error) == "ssim" ? 1.0 - cell["ssim"].get<double>() : cell["flip"].get<double>();
        front.emplace_back(cell["speedup"].get<double>(), value, cell_settings_label(cell));
      }
      std::sort(front.begin(), front.end());
      std::string list;
      for (const auto& [speedup, value, label] : front) {
        list +=
            (list.empty() ? "" : ", ") + label + " (" + number(speedup, "%.2fx") + ", " + number(value, "%.4f") + ")";
      }
      out << "| " << scene << " | " << name << " | " << list << " |\n";
    }
  }
  return out.str();
}

}  // namespace fovlab::bench
