#pragma once
// fovlab bench, step 3: the trade-off of a scene's cells between speed and error. A cell is on the
// Pareto front when no other cell is at least as fast and at most as wrong, and better in one of
// the two. Charts: speed-up against the error, one point per cell labelled with its settings, the
// front marked and connected (SVG, analysis/report/svg_chart.h).
#include <string>
#include <vector>

namespace fovlab::bench {

struct TradeOff {
  double speedup = 1.0;  // against GT of the same spp (higher is better)
  double error = 0.0;    // against GT of the same spp, e.g. FLIP or 1 - SSIM (lower is better)
};

// One flag per point: true when no other point dominates it. Points with a non-finite value are
// never on the front and dominate nothing. Equal points do not dominate each other.
std::vector<bool> pareto_front(const std::vector<TradeOff>& points);

struct ChartCell {
  std::string method;  // "gt", "ipr" or "fipr"
  int spp = 1;
  int refresh = 1;         // FIPR only
  double fovea_deg = 0.0;  // FIPR only
  TradeOff trade_off;
  bool on_front = false;
  double shaded_over_reference = 0.0;  // sampling models: shaded samples over RMFR's (0: not known)
};

// "4/2/7.5" (spp/refresh/fovea degrees) for FIPR, "ipr 4" for IPR, "gt" for GT, "kfr 1 (0.99x
// rmfr's samples)" for a sampling model (its work against RMFR's at the same sigma).
std::string cell_label(const ChartCell& cell);

// The chart of one scene: GT once (its cells all sit at speed-up 1, error 0), IPR, FIPR one series
// per spp, each point labelled by cell_label, and the front as a line through its points (by
// speed-up) with its own markers.
std::string pareto_chart_svg(const std::string& title, const std::string& error_label,
                             const std::vector<ChartCell>& cells);

}  // namespace fovlab::bench
