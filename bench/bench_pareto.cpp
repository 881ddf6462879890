#include "bench/bench_pareto.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "analysis/report/svg_chart.h"
#include "core/number_text.h"

namespace fovlab::bench {

namespace {

bool finite(const TradeOff& point) { return std::isfinite(point.speedup) && std::isfinite(point.error); }

bool dominates(const TradeOff& a, const TradeOff& b) {
  return a.speedup >= b.speedup && a.error <= b.error && (a.speedup > b.speedup || a.error < b.error);
}

void add_point(analysis::XySeries& series, const ChartCell& cell) {
  series.x.push_back(cell.trade_off.speedup);
  series.y.push_back(cell.trade_off.error);
  series.point_labels.push_back(cell_label(cell));
}

}  // namespace

std::vector<bool> pareto_front(const std::vector<TradeOff>& points) {
  std::vector<bool> front(points.size(), false);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!finite(points[i])) continue;
    front[i] = std::none_of(points.begin(), points.end(),
                            [&](const TradeOff& other) { return finite(other) && dominates(other, points[i]); });
  }
  return front;
}

std::string cell_label(const ChartCell& cell) {
  if (cell.method == "fipr") {
    return std::to_string(cell.spp) + "/" + std::to_string(cell.refresh) + "/" + format_number(cell.fovea_deg, 6);
  }
  if (cell.method == "ipr") return "ipr " + std::to_string(cell.spp);
  if (cell.method != "gt") {  // a sampling model
    std::string label = cell.method + " " + std::to_string(cell.spp);
    if (cell.shaded_over_reference > 0)
      label += " (" + format_number(cell.shaded_over_reference, 3) + "x rmfr's samples)";
    return label;
  }
  return cell.method;
}

std::string pareto_chart_svg(const std::string& title, const std::string& error_label,
                             const std::vector<ChartCell>& cells) {
  analysis::XyChart chart;
  chart.title = title;
  chart.x_label = "speed-up against GT of the same spp (GT ms / ms, median GPU)";
  chart.y_label = error_label;
  chart.y_min = 0.0;

  analysis::XySeries gt{"GT (speed-up 1, error 0)", analysis::XySeries::Style::points, {}, {}, {}, {}, {}};
  analysis::XySeries ipr{"IPR (label: ipr spp)", analysis::XySeries::Style::points, {}, {}, {}, {}, {}};
  std::map<int, analysis::XySeries> fipr_by_spp;
  std::map<std::string, analysis::XySeries> model_series;  // Ye et al. 2022's sampling models, one series each
  std::vector<std::pair<double, double>> front;
  for (const ChartCell& cell : cells) {
    if (cell.method == "gt") {
      if (gt.x.empty()) add_point(gt, cell);
    } else if (cell.method == "ipr") {
      add_point(ipr, cell);
    } else if (cell.method != "fipr") {
      analysis::XySeries& series = model_series[cell.method];
      series.label = cell.method + " (label: method spp)";
      add_point(series, cell);
    } else {
      analysis::XySeries& series = fipr_by_spp[cell.spp];
      series.label = "FIPR " + std::to_string(cell.spp) + " spp (spp/refresh/fovea deg)";
      add_point(series, cell);
    }
    if (cell.on_front) front.emplace_back(cell.trade_off.speedup, cell.trade_off.error);
  }
  std::sort(front.begin(), front.end());
  front.erase(std::unique(front.begin(), front.end()), front.end());

  if (!gt.x.empty()) chart.series.push_back(gt);
  if (!ipr.x.empty()) chart.series.push_back(ipr);
  for (auto& [spp, series] : fipr_by_spp) chart.series.push_back(std::move(series));
  for (auto& [method, series] : model_series) chart.series.push_back(std::move(series));
  analysis::XySeries line{"", analysis::XySeries::Style::line, {}, {}, {}, {}, {}};
  analysis::XySeries markers{"Pareto front (not dominated)", analysis::XySeries::Style::points, {}, {}, {}, {}, {}};
  for (const auto& [speedup, error] : front) {
    line.x.push_back(speedup);
    line.y.push_back(error);
  }
  markers.x = line.x;
  markers.y = line.y;
  chart.series.push_back(std::move(line));
  chart.series.push_back(std::move(markers));
  return analysis::render_xy_chart_svg(chart);
}

}  // namespace fovlab::bench
