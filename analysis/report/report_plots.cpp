#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "analysis/report/report_formats.h"
#include "analysis/report/svg_chart.h"
#include "core/number_text.h"

namespace fovlab::analysis::report_detail {
namespace {

constexpr int kCurveSamples = 200;
constexpr size_t kGroupsInOnePlot = 4;  // more groups: one share plot each
constexpr size_t kTrackPlots = 24;      // participants drawn one plot each (adaptive tracks, frame intervals)

// Anything outside [A-Za-z0-9_-] becomes '_' (a UTF-8 character: one '_' a byte).
std::string safe_name(const std::string& text) {
  std::string name;
  for (char c : text) {
    const bool keep =
        (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    name += keep ? c : '_';
  }
  return name.empty() ? "unnamed" : name;
}

// A group's file stem: `prefix` and its scene, then its variant where it has one
// ("thresholds_histogram_courtyard_fipr").
std::string group_file_stem(const std::string& prefix, const GroupKey& group) {
  std::string stem = prefix + safe_name(group.scene);
  if (!group.variant.empty()) stem += "_" + safe_name(group.variant);
  return stem;
}

// A file name not yet taken: stem.svg, else stem_2.svg, stem_3.svg, ...
std::string unique_svg_name(const std::string& stem, std::set<std::string>& taken) {
  std::string name = stem + ".svg";
  for (int i = 2; taken.count(name); ++i) name = stem + "_" + std::to_string(i) + ".svg";
  taken.insert(name);
  return name;
}

bool is_rating(const AnalysisResult& result) { return result.protocol == ProtocolKind::rating; }

std::string level_axis_label(const AnalysisResult& result) {
  return result.level_parameter.empty() ? "level" : "level (" + result.level_parameter + ")";
}

// The headline of `group`, if the analysis gave one.
const Headline* headline_of(const AnalysisResult& result, const GroupKey& group) {
  for (const Headline& headline : result.headlines)
    if (headline.group == group) return &headline;
  return nullptr;
}

// The headline is an estimated threshold on the level axis (not a preference share): marked on its
// plots. A biased or not estimable one is not (the plot's caption says why), as the Headline table
// prints no number for it.
bool marks_level(const Headline* headline) {
  return headline && headline->status == HeadlineStatus::estimated && headline->quantity != "preference share" &&
         headline_has_value(*headline);
}

// Levels spaced evenly on a log scale (4, 8, 16, ..., or 1, 2, 5, 10, ...): all positive, at least
// three, spanning a factor of 4 or more, with gaps more even in log than in linear terms. Their
// plots get a log axis, where such levels are evenly spread instead of crowded at one end.
bool log_spaced(std::vector<double> levels) {
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  if (levels.size() < 3 || !(levels.front() > 0.0) || levels.back() < 4.0 * levels.front()) return false;
  const auto spread = [](const std::vector<double>& gaps) {  // coefficient of variation
    double mean = 0.0, squares = 0.0;
    for (double gap : gaps) mean += gap / double(gaps.size());
    for (double gap : gaps) squares += (gap - mean) * (gap - mean) / double(gaps.size());
    return std::sqrt(squares) / mean;
  };
  std::vector<double> linear, logarithmic;
  for (size_t i = 1; i < levels.size(); ++i) {
    linear.push_back(levels[i] - levels[i - 1]);
    logarithmic.push_back(std::log(levels[i] / levels[i - 1]));
  }
  return spread(logarithmic) < spread(linear);
}

// Share of answers for the test stimulus per level (Polychronakis et al. 2023, Fig. 9), one series
// per group; rating studies: the mean rating per level (error bars ±1 SD) against the cutoff 2.
// `only`: the plot of that group alone (one of the small multiples drawn for many groups).
std::optional<Plot> share_per_level_plot(const AnalysisResult& result,
                                         const std::optional<GroupKey>& only = std::nullopt) {
  const bool rating = is_rating(result);
  std::map<GroupKey, XySeries> by_group;
  std::vector<GroupKey> order;  // first appearance, so the legend follows the table
  for (const ConditionRow& row : result.conditions) {
    if (!row.level || !std::isfinite(*row.level) || row.n == 0) continue;
    if (only && !(row.group == *only)) continue;
    double y = row.proportion;
    double lower = row.interval.lower;
    double upper = row.interval.upper;
    if (rating) {
      if (!row.mean_rating || !std::isfinite(*row.mean_rating)) continue;
      y = *row.mean_rating;
      const double sd = row.sd_rating && std::isfinite(*row.sd_rating) ? *row.sd_rating : 0.0;
      lower = y - sd;
      upper = y + sd;
    }
    if (!std::isfinite(y)) continue;
    if (!by_group.count(row.group)) order.push_back(row.group);
    XySeries& series = by_group[row.group];
    series.x.push_back(*row.level);
    series.y.push_back(y);
    series.y_lower.push_back(lower);
    series.y_upper.push_back(upper);
  }
  if (order.empty()) return std::nullopt;
  XyChart chart;
  // One meaning per title: the share of trials in favour of the test, named as the protocol counts it.
  const std::string favour(result.rules().judged_words);
  chart.title = result.study + (only ? ", " + only->label() : std::string()) +
                (rating ? ": mean rating per level" : ": share of trials the test was " + favour + ", per level");
  chart.x_label = level_axis_label(result);
  chart.y_label = rating ? "mean rating (1-3), bars: ±1 SD" : "share " + favour + " (k/n), bars: 95 % Clopper-Pearson";
  chart.y_min = rating ? 1.0 : 0.0;
  chart.y_max = rating ? 3.0 : 1.0;
  chart.horizontal_lines = {rating ? result.rating_cutoff : 0.5};
  chart.x_log = log_spaced(result.levels);
  // With several groups, each is shifted a little along x (about 6 px apart, at most 30 % of the
  // smallest gap between levels) so points and bars at one level do not hide each other.
  double offset_step = 0.0;
  if (order.size() > 1) {
    std::vector<double> levels;
    for (const auto& entry : by_group) levels.insert(levels.end(), entry.second.x.begin(), entry.second.x.end());
    std::sort(levels.begin(), levels.end());
    levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
    if (levels.size() > 1) {
      double gap = levels.back() - levels.front();
      for (std::size_t i = 1; i < levels.size(); ++i) gap = std::min(gap, levels[i] - levels[i - 1]);
      offset_step =
          std::min(0.017 * (levels.back() - levels.front()), 0.3 * gap / static_cast<double>(order.size() - 1));
    }
  }
  if (chart.x_log) {  // the same shift as a share of the log range: a factor, not a difference
    offset_step = 0.0;
    if (order.size() > 1 && !result.levels.empty()) {
      const auto [lowest, highest] = std::minmax_element(result.levels.begin(), result.levels.end());
      offset_step = 0.017 * std::log10(*highest / *lowest);
    }
  }
  for (std::size_t g = 0; g < order.size(); ++g) {
    XySeries series = by_group[order[g]];
    const double offset = offset_step * (static_cast<double>(g) - static_cast<double>(order.size() - 1) / 2);
    for (double& x : series.x) x = chart.x_log ? x * std::pow(10.0, offset) : x + offset;
    series.label = order[g].label();
    series.style = XySeries::Style::points;
    chart.series.push_back(std::move(series));
  }
  Plot plot;
  plot.file_name = "share_per_level.svg";
  plot.caption = rating ? "Mean rating per level and group (bars: ±1 SD); dashed: the cutoff 2 (minimal difference)."
                        : "Share of trials where the test was " + std::string(result.rules().judged_words) +
                              ", per level and group (bars: 95 % Clopper-Pearson intervals); dashed: 1/2, the null "
                              "hypothesis of the test.";
  if (offset_step > 0.0) plot.caption += " Groups are shifted slightly along x to keep them apart.";
  plot.svg = render_xy_chart_svg(chart);
  return plot;
}

// The headline of a group as a legend label, "headline 13.81 [12.96, 14.71]" after `prefix`; the
// interval left out when the legend would cut it (the band shows it).
std::string headline_label(const std::string& prefix, const Headline& headline) {
  const std::string full = prefix + "headline " + headline_value_text(headline);
  return full.size() <= 36 ? full : prefix + "headline " + html_number(headline.value);
}

// Marks a group's headline on a chart: its value as a dashed vertical line, its 95 % interval as a
// band (an unbounded end drawn to the edge of [lo, hi]). `prefix` names the group in the legend
// ("" when the chart shows one group); `colour` is the group's palette index (none: grey).
void mark_headline(XyChart& chart, const Headline& headline, const std::string& prefix,
                   std::optional<std::size_t> colour, double lo, double hi) {
  if (headline.lower && headline.upper) {
    const double band_lower = std::max(*headline.lower, lo);
    const double band_upper = std::min(*headline.upper, hi);
    if (band_lower <= band_upper) chart.bands.push_back({"", band_lower, band_upper, colour});
  }
  chart.vertical_lines.push_back({headline_label(prefix, headline), *headline.value, colour});
}

// Why a group's plot shows no threshold mark: "blur: not estimable (the fit's threshold lies
// outside the tested levels)".
std::string unmarked_headline_note(const Headline& headline) {
  return headline.group.label() + ": " + headline_status_name(headline.status) +
         (headline.reason.empty() ? std::string() : " (" + headline.reason + ")");
}

// Each included participant's share of trials with a difference reported per level, where their
// data give one: adaptive tracks of the group (block = the group's scene, or any block for "all"),
// at levels they were shown at least twice. Constant-stimulus designs keep no per-participant
// counts in the result.
XySeries participant_proportions(const AnalysisResult& result, const GroupKey& group) {
  XySeries points;
  points.style = XySeries::Style::points;
  points.small = true;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.excluded) continue;
    std::map<double, std::pair<int, int>> by_level;  // level -> (trials, seen)
    for (const AdaptiveTrackResult& track : participant.tracks) {
      if (track.variant != group.variant || (group.scene != "all" && track.block != group.scene)) continue;
      for (size_t i = 0; i < track.levels.size() && i < track.seen.size(); ++i) {
        auto& [trials, seen] = by_level[track.levels[i]];
        ++trials;
        seen += track.seen[i] ? 1 : 0;
      }
    }
    for (const auto& [level, counts] : by_level) {
      if (counts.first < 2 || !std::isfinite(level)) continue;
      points.x.push_back(level);
      points.y.push_back(double(counts.second) / double(counts.first));
    }
  }
  return points;
}

// Data (share of "difference reported" with Clopper-Pearson intervals), fitted curves and the
// headline threshold (a dashed line and its interval as a band) of the groups of one scene: one
// group alone gets every fitted shape; several variants are overlaid, one colour each, with their
// first fit. Each participant's proportions, where the data give them, are small points.
std::optional<Plot> psychometric_plot(const AnalysisResult& result, const std::vector<const GroupFit*>& groups,
                                      std::set<std::string>& taken) {
  if (groups.empty()) return std::nullopt;
  const bool overlay = groups.size() > 1;
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (const GroupFit* group : groups)
    for (const LevelCounts& counts : group->data) {
      if (counts.n == 0 || counts.k > counts.n || !std::isfinite(counts.level)) continue;
      lo = std::min(lo, counts.level);
      hi = std::max(hi, counts.level);
    }
  if (!(lo < hi)) {  // one level or none: the study's levels give the range of the curves
    for (double level : result.levels) {
      if (!std::isfinite(level)) continue;
      lo = std::min(lo, level);
      hi = std::max(hi, level);
    }
  }
  XyChart chart;
  const GroupFit& first = *groups.front();
  // The complement of the share plot's quantity: what the psychometric function models.
  chart.title = (overlay ? first.group.scene : first.group.label()) + ": P(difference reported) = 1 - share " +
                std::string(result.rules().judged_words);
  chart.x_label = level_axis_label(result);
  chart.y_label = "P(difference reported)";
  chart.y_min = 0.0;
  chart.y_max = 1.0;
  chart.x_log = log_spaced(result.levels) && lo > 0.0;
  std::vector<std::string> unmarked;
  bool any_participants = false, any_data = false;
  // Overlaid variants share levels: each one's points are shifted a little along x (as in the share
  // plot: 1.7 % of the range, at most 30 % of the smallest gap; on a log axis a factor).
  double offset_step = 0.0;
  if (overlay && lo < hi) {
    std::vector<double> levels = result.levels;
    std::sort(levels.begin(), levels.end());
    double gap = hi - lo;
    for (size_t i = 1; i < levels.size(); ++i)
      if (levels[i] > levels[i - 1]) gap = std::min(gap, levels[i] - levels[i - 1]);
    offset_step = chart.x_log ? 0.017 * std::log10(hi / lo)
                              : std::min(0.017 * (hi - lo), 0.3 * gap / static_cast<double>(groups.size() - 1));
  }
  for (size_t g = 0; g < groups.size(); ++g) {
    const GroupFit& group = *groups[g];
    const double offset = offset_step * (static_cast<double>(g) - static_cast<double>(groups.size() - 1) / 2);
    const auto shifted = [&](double x) { return chart.x_log ? x * std::pow(10.0, offset) : x + offset; };
    const std::optional<std::size_t> colour = overlay ? std::optional<std::size_t>(g) : std::nullopt;
    const std::string name = group.group.variant.empty() ? "(no variant)" : group.group.variant;
    XySeries data;
    data.label = overlay ? name + ": data" : "data";
    data.style = XySeries::Style::points;
    data.colour = colour.value_or(0);
    for (const LevelCounts& counts : group.data) {
      if (counts.n == 0 || counts.k > counts.n || !std::isfinite(counts.level)) continue;
      const ProportionInterval interval = clopper_pearson_interval(counts.k, counts.n);
      data.x.push_back(shifted(counts.level));
      data.y.push_back(static_cast<double>(counts.k) / static_cast<double>(counts.n));
      data.y_lower.push_back(interval.lower);
      data.y_upper.push_back(interval.upper);
    }
    XySeries participants = participant_proportions(result, group.group);
    for (double& x : participants.x) x = shifted(x);
    if (!participants.x.empty()) {
      participants.colour = data.colour;
      if (!any_participants) participants.label = "each participant";
      any_participants = true;
      chart.series.push_back(std::move(participants));
    }
    if (!data.x.empty()) {
      any_data = true;
      chart.series.push_back(data);
    }
    if (lo < hi) {
      for (size_t f = 0; f < group.fits.size() && (f == 0 || !overlay); ++f) {
        const PsychometricFit& fit = group.fits[f];
        XySeries curve;
        curve.style = XySeries::Style::line;
        if (overlay) curve.colour = g;
        else curve.colour = f + 1;
        // "cumulative_normal" is the name in the tables; the legend has room for a short one.
        const std::string shape =
            fit.model.shape == PsychometricShape::cumulative_normal ? "normal" : shape_name(fit.model.shape);
        // Overlaid: the variant and the shape (the headline's line gives the number).
        curve.label = overlay ? name + ": " + shape + " fit"
                              : shape + " fit, threshold " + format_number(fit.model.parameters.threshold, kHtmlDigits);
        for (int i = 0; i < kCurveSamples; ++i) {
          const double t = double(i) / (kCurveSamples - 1);
          const double level = chart.x_log ? lo * std::pow(hi / lo, t) : lo + (hi - lo) * t;
          curve.x.push_back(level);
          curve.y.push_back(fit.model.p_report(level));
        }
        chart.series.push_back(std::move(curve));
      }
    }
    const Headline* headline = headline_of(result, group.group);
    if (marks_level(headline)) {
      mark_headline(chart, *headline, overlay ? name + ": " : "", colour, lo, hi);
    } else if (headline) {
      unmarked.push_back(unmarked_headline_note(*headline));
    } else if (!group.fits.empty() && !overlay) {
      // No headline from the analysis: the first fit's profile interval, as before headlines existed.
      const ParameterInterval& interval = group.fits.front().threshold_interval;
      const double band_lower = std::max(interval.lower, lo);
      const double band_upper = std::min(interval.upper, hi);
      if (band_lower <= band_upper)  // false for NaN ends and for an interval beyond the tested levels
        chart.bands.push_back({std::string("threshold CI (") + shape_name(group.fits.front().model.shape) + ")",
                               band_lower, band_upper, std::nullopt});
    }
  }
  if (chart.series.empty()) return std::nullopt;
  Plot plot;
  plot.file_name = unique_svg_name(
      overlay ? "psychometric_" + safe_name(first.group.scene) : group_file_stem("psychometric_", first.group), taken);
  plot.caption =
      "Psychometric fits for " + (overlay ? first.group.scene + ", its variants overlaid" : first.group.label()) +
      ": share of trials with a difference reported (bars: 95 % Clopper-Pearson), the fitted curve" +
      (overlay ? " of each variant" : "s") +
      (chart.vertical_lines.empty() ? std::string()
                                    : ", and the headline threshold (dashed) with its 95 % interval (shaded)");
  if (any_participants) plot.caption += "; small points: each participant's share at a level they saw at least twice";
  plot.caption += ".";
  if (offset_step > 0.0) plot.caption += " The variants' points are shifted slightly along x to keep them apart.";
  if (!any_data) plot.caption += " No pooled data to show.";
  if (!unmarked.empty()) plot.caption += " No threshold marked for " + joined(unmarked, "; ") + ".";
  plot.svg = render_xy_chart_svg(chart);
  return plot;
}

// Each included participant's threshold as a point (pair, ramp, slider), one row a participant, the
// variants of one scene overlaid (one colour each, rows shifted a little apart), with the headline
// (the mean over participants: a dashed line) and its 95 % interval (shaded).
std::vector<Plot> participant_threshold_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<std::string> scenes;
  std::map<std::string, std::vector<GroupKey>> groups_of;  // scene -> its groups, first appearance first
  std::vector<const ParticipantRow*> rows;                 // participants with a threshold, in path order
  for (const ParticipantRow& participant : result.participants) {
    if (participant.excluded) continue;
    bool any = false;
    for (const ParticipantThreshold& threshold : participant.thresholds) {
      if (!threshold.level || !std::isfinite(*threshold.level)) continue;
      any = true;
      auto& groups = groups_of[threshold.group.scene];
      if (groups.empty()) scenes.push_back(threshold.group.scene);
      if (std::find(groups.begin(), groups.end(), threshold.group) == groups.end()) groups.push_back(threshold.group);
    }
    if (any) rows.push_back(&participant);
  }
  std::vector<Plot> plots;
  for (const std::string& scene : scenes) {
    const std::vector<GroupKey>& groups = groups_of[scene];
    const bool overlay = groups.size() > 1;
    XyChart chart;
    chart.title = result.study + ", " + scene + ": each participant's threshold";
    chart.x_label = "threshold " + level_axis_label(result);
    chart.y_label = "participant (in log-path order)";
    chart.y_min = 0.0;
    chart.y_max = double(rows.size()) + 1.0;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double level : result.levels) {
      lo = std::min(lo, level);
      hi = std::max(hi, level);
    }
    std::vector<std::string> unmarked;
    for (size_t g = 0; g < groups.size(); ++g) {
      const GroupKey& group = groups[g];
      const std::string name = group.variant.empty() ? "(no variant)" : group.variant;
      const double shift = overlay ? 0.5 * (double(g) - double(groups.size() - 1) / 2) / double(groups.size()) : 0.0;
      XySeries points;
      points.style = XySeries::Style::points;
      points.colour = g;
      points.label = overlay ? name + ": each participant" : "each participant";
      for (size_t r = 0; r < rows.size(); ++r)
        for (const ParticipantThreshold& threshold : rows[r]->thresholds) {
          if (!(threshold.group == group) || !threshold.level || !std::isfinite(*threshold.level)) continue;
          points.x.push_back(*threshold.level);
          points.y.push_back(double(r + 1) + shift);
          if (!overlay && rows.size() <= kTrackPlots) points.point_labels.push_back(rows[r]->participant);
          lo = std::min(lo, *threshold.level);
          hi = std::max(hi, *threshold.level);
        }
      if (!points.point_labels.empty() && points.point_labels.size() != points.x.size()) points.point_labels.clear();
      chart.series.push_back(std::move(points));
    }
    for (size_t g = 0; g < groups.size(); ++g) {
      const std::string name = groups[g].variant.empty() ? "(no variant)" : groups[g].variant;
      const Headline* headline = headline_of(result, groups[g]);
      if (marks_level(headline)) {
        mark_headline(chart, *headline, overlay ? name + ": " : "", g, lo, hi);
      } else if (headline) {
        unmarked.push_back(unmarked_headline_note(*headline));
      } else {
        // No headline from the analysis: the paper's mean over participants and its interval.
        for (const GroupThreshold& threshold : result.thresholds)
          if (threshold.group == groups[g] && threshold.mean) {
            if (threshold.mean_lower && threshold.mean_upper)
              chart.bands.push_back({"", *threshold.mean_lower, *threshold.mean_upper, g});
            chart.vertical_lines.push_back(
                {(overlay ? name + ": " : std::string()) + "mean " +
                     html_value_with_interval(threshold.mean, threshold.mean_lower, threshold.mean_upper),
                 *threshold.mean, g});
          }
      }
    }
    chart.x_log = log_spaced(result.levels) && lo > 0.0;
    Plot plot;
    plot.file_name = unique_svg_name("participant_thresholds_" + safe_name(scene), taken);
    plot.caption = "Each included participant's threshold, " + scene +
                   (overlay ? " (variants overlaid, each row shifted a little per variant)" : std::string()) +
                   (chart.vertical_lines.empty()
                        ? std::string(".")
                        : "; dashed: each group's headline (its method in the Headline table) with its 95 % interval "
                          "(shaded).");
    if (!unmarked.empty()) plot.caption += " No threshold marked for " + joined(unmarked, "; ") + ".";
    plot.svg = render_xy_chart_svg(chart);
    plots.push_back(std::move(plot));
  }
  return plots;
}

// Ye et al. 2022, Figure 9: one heat map per block (and for every block pooled) of the mean score per pair
// of the two grid parameters over every level, coloured on the score's scale 1..3, the best pair
// outlined.
std::vector<Plot> rating_grid_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<Plot> plots;
  if (!result.rating_grid) return plots;
  const RatingGrid& grid = *result.rating_grid;
  for (const GridMap& map : grid.maps) {
    if (map.level) continue;  // per level: in the CSV and JSON only
    HeatMap heat;
    heat.title = map.scene + ": mean score (1-3) over every level";
    heat.x_label = grid.x_key;
    heat.y_label = grid.y_key;
    heat.x_values = grid.x_values;
    heat.y_values = grid.y_values;
    for (const GridCell& cell : map.cells) heat.cells.push_back(cell.mean_score.value_or(std::nan("")));
    heat.cell_format = "%.2f";
    heat.colour_min = 1.0;
    heat.colour_max = 3.0;
    heat.marked_cells = map.best;
    heat.marked_label = map.best.size() > 1 ? "outlined: highest mean (a tie)" : "outlined: highest mean";
    Plot plot;
    plot.file_name = unique_svg_name("rating_grid_" + safe_name(map.scene), taken);
    plot.caption = "Pilot grid, " + map.scene +
                   ": mean score (3 identical, 2 minimal difference, 1 significant "
                   "difference) per pair of " +
                   grid.x_key + " and " + grid.y_key +
                   ", each participant's mean over every level, then the mean over participants; grey: no trial; "
                   "outlined: the highest mean" +
                   (map.best.size() > 1 ? " (a tie)" : "") + ".";
    plot.svg = render_heat_map_svg(heat);
    plots.push_back(std::move(plot));
  }
  return plots;
}

// Bins centred on the study's levels (edges midway between neighbouring levels); without levels, on
// the distinct thresholds themselves.
std::vector<double> level_bin_edges(std::vector<double> centres) {
  centres.erase(std::remove_if(centres.begin(), centres.end(), [](double v) { return !std::isfinite(v); }),
                centres.end());
  std::sort(centres.begin(), centres.end());
  centres.erase(std::unique(centres.begin(), centres.end()), centres.end());
  if (centres.empty()) return {};
  if (centres.size() == 1) return {centres[0] - 0.5, centres[0] + 0.5};
  std::vector<double> edges = {centres[0] - (centres[1] - centres[0]) / 2};
  for (std::size_t i = 1; i < centres.size(); ++i) edges.push_back((centres[i - 1] + centres[i]) / 2);
  const std::size_t last = centres.size() - 1;
  edges.push_back(centres[last] + (centres[last] - centres[last - 1]) / 2);
  return edges;
}

// Per-participant thresholds of the included participants (Polychronakis et al. 2021, Fig. 7): pooled over the
// groups, and one histogram a group when there are several.
std::vector<Plot> threshold_histograms(const AnalysisResult& result, std::set<std::string>& taken) {
  std::map<GroupKey, std::vector<double>> by_group;
  std::vector<double> all;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.excluded) continue;
    for (const ParticipantThreshold& threshold : participant.thresholds) {
      if (!threshold.level || !std::isfinite(*threshold.level)) continue;
      by_group[threshold.group].push_back(*threshold.level);
      all.push_back(*threshold.level);
    }
  }
  if (all.empty()) return {};
  std::vector<Plot> plots;
  auto make = [&](const std::string& stem, const std::string& what, const std::vector<double>& values) {
    Histogram histogram;
    histogram.title = result.study + ": per-participant thresholds" + what;
    histogram.x_label = "threshold " + level_axis_label(result);
    histogram.values = values;
    histogram.bin_edges = level_bin_edges(result.levels.empty() ? values : result.levels);
    Plot plot;
    plot.file_name = unique_svg_name(stem, taken);
    plot.caption = "Per-participant thresholds" + what + " (included participants; one bin a level).";
    plot.svg = render_histogram_svg(histogram);
    plots.push_back(std::move(plot));
  };
  make("thresholds_histogram", by_group.size() > 1 ? ", all groups" : "", all);
  if (by_group.size() > 1) {
    for (const auto& [group, values] : by_group) {
      make(group_file_stem("thresholds_histogram_", group), ", " + group.label(), values);
    }
  }
  return plots;
}

// A participant's adaptive tracks: each one's level trial by trial (a line), the trials whose answer
// saw the difference and those that did not, a staircase's reversals, and each threshold (dashed).
// At most kTrackPlots participants are drawn; adaptive_tracks.csv holds every track.

std::vector<Plot> adaptive_track_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<Plot> plots;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.tracks.empty() || plots.size() >= kTrackPlots) continue;
    XyChart chart;
    chart.title = participant.participant + ": adaptive tracks";
    chart.x_label = "trial of the track";
    chart.y_label = level_axis_label(result);
    XySeries seen{"seen", XySeries::Style::points, {}, {}, {}, {}, {}};
    XySeries not_seen{"not seen", XySeries::Style::points, {}, {}, {}, {}, {}};
    XySeries reversals{"reversal", XySeries::Style::points, {}, {}, {}, {}, {}};
    for (const AdaptiveTrackResult& track : participant.tracks) {
      XySeries line;
      line.style = XySeries::Style::line;
      line.label = (track.variant.empty() ? "" : track.variant + ", ") +
                   (track.start_level ? "start " + format_number(*track.start_level, kHtmlDigits) : track.procedure);
      for (size_t i = 0; i < track.levels.size(); ++i) {
        line.x.push_back(double(i + 1));
        line.y.push_back(track.levels[i]);
        XySeries& answer = track.seen[i] ? seen : not_seen;
        answer.x.push_back(double(i + 1));
        answer.y.push_back(track.levels[i]);
      }
      for (int trial : track.reversal_trials) {
        reversals.x.push_back(double(trial + 1));
        reversals.y.push_back(track.levels.at(static_cast<size_t>(trial)));
      }
      if (track.threshold) chart.horizontal_lines.push_back(*track.threshold);
      chart.series.push_back(std::move(line));
    }
    for (XySeries* answers : {&seen, &not_seen, &reversals})
      if (!answers->x.empty()) chart.series.push_back(std::move(*answers));
    Plot plot;
    plot.file_name = unique_svg_name("adaptive_tracks_" + safe_name(participant.participant), taken);
    plot.caption = participant.participant +
                   "'s adaptive tracks: the level of each trial, its answer, a staircase's "
                   "reversals, and each threshold (dashed: a staircase's mean of its last reversals, QUEST+'s "
                   "posterior mean).";
    plot.svg = render_xy_chart_svg(chart);
    plots.push_back(std::move(plot));
  }
  return plots;
}

// The histogram of a frame-interval summary: bins a sixteenth of a refresh period wide (about 1 ms
// at 60 Hz, so a display's jitter shows), centred on
// multiples of it (an interval of exactly one period sits mid-bar), from 0 to 3 to 6 periods
// (longer intervals in the last bar), with the late limit (1.5 periods) marked. Without a refresh
// rate the median stands for the period.
Histogram frame_interval_histogram(const FrameIntervalSummary& frames, const std::string& title) {
  Histogram histogram;
  histogram.title = title;
  histogram.x_label = "interval between presented refreshes (ms)";
  for (const auto& [us, count] : frames.count_by_us) {
    histogram.values.push_back(static_cast<double>(us) / 1e3);
    histogram.counts.push_back(static_cast<double>(count));
  }
  const double period_ms = frames.refresh_hz ? 1e3 / *frames.refresh_hz : frames.median_ms.value_or(0.0);
  if (period_ms > 0.0 && std::isfinite(period_ms)) {
    const double periods = std::clamp(std::ceil(frames.max_ms.value_or(period_ms) / period_ms), 3.0, 6.0);
    const double width = period_ms / 16;
    for (int k = 0; k <= static_cast<int>(periods * 16) + 1; ++k) histogram.bin_edges.push_back((k - 0.5) * width);
    histogram.bin_edges.front() = 0.0;
    histogram.count_labels = false;
    if (frames.refresh_hz) {
      histogram.vertical_lines = {kLateRefreshPeriods * period_ms};
      histogram.vertical_lines_label = "dashed: late beyond 1.5 refresh periods (" +
                                       format_number(kLateRefreshPeriods * period_ms, kHtmlDigits) + " ms)";
    }
  }
  return histogram;
}

// The study's frame-interval histogram, then one a session (at most kTrackPlots).
std::vector<Plot> frame_interval_plots(const AnalysisResult& result, std::set<std::string>& taken) {
  std::vector<Plot> plots;
  const FrameIntervalSummary study = result.frame_intervals;
  if (study.intervals == 0) return plots;
  Plot plot;
  plot.file_name = unique_svg_name("frame_intervals", taken);
  plot.caption = "Intervals between presented refreshes, every included session pooled (" +
                 std::to_string(study.intervals) + " intervals).";
  plot.svg = render_histogram_svg(frame_interval_histogram(study, result.study + ": frame intervals, every session"));
  plots.push_back(std::move(plot));
  size_t sessions = 0;
  for (const ParticipantRow& participant : result.participants) {
    if (participant.frame_intervals.intervals == 0 || sessions >= kTrackPlots) continue;
    ++sessions;
    Plot session;
    session.file_name = unique_svg_name("frame_intervals_" + safe_name(participant.participant), taken);
    session.caption = participant.participant + "'s session: intervals between presented refreshes (" +
                      std::to_string(participant.frame_intervals.intervals) + " intervals).";
    session.svg = render_histogram_svg(
        frame_interval_histogram(participant.frame_intervals, participant.participant + ": frame intervals"));
    plots.push_back(std::move(session));
  }
  return plots;
}
}  // namespace

ReportPlots report_plots(const AnalysisResult& result) {
  std::set<std::string> taken = {"share_per_level.svg"};
  std::vector<Plot> plots;
  // Up to four groups share one plot; more get one plot each (small multiples), which stay readable.
  std::vector<GroupKey> groups;
  for (const ConditionRow& row : result.conditions)
    if (row.level && std::find(groups.begin(), groups.end(), row.group) == groups.end()) groups.push_back(row.group);
  if (groups.size() <= kGroupsInOnePlot) {
    if (auto plot = share_per_level_plot(result)) plots.push_back(std::move(*plot));
  } else {
    for (const GroupKey& group : groups)
      if (auto plot = share_per_level_plot(result, group)) {
        plot->file_name = unique_svg_name(group_file_stem("share_per_level_", group), taken);
        plots.push_back(std::move(*plot));
      }
  }
  for (Plot& plot : rating_grid_plots(result, taken)) plots.push_back(std::move(plot));
  // The psychometric plots: a scene's variants overlaid on one (up to four), else one a group.
  std::vector<std::vector<const GroupFit*>> by_scene;
  for (const GroupFit& group : result.fits) {
    auto same = std::find_if(by_scene.begin(), by_scene.end(), [&](const std::vector<const GroupFit*>& fits) {
      return fits.front()->group.scene == group.group.scene;
    });
    if (same == by_scene.end()) by_scene.push_back({&group});
    else same->push_back(&group);
  }
  for (const std::vector<const GroupFit*>& scene : by_scene) {
    if (scene.size() <= kGroupsInOnePlot) {
      if (auto plot = psychometric_plot(result, scene, taken)) plots.push_back(std::move(*plot));
    } else {
      for (const GroupFit* group : scene)
        if (auto plot = psychometric_plot(result, {group}, taken)) plots.push_back(std::move(*plot));
    }
  }
  for (Plot& plot : participant_threshold_plots(result, taken)) plots.push_back(std::move(plot));
  for (Plot& plot : threshold_histograms(result, taken)) plots.push_back(std::move(plot));
  for (Plot& plot : adaptive_track_plots(result, taken)) plots.push_back(std::move(plot));
  std::vector<Plot> frame_plots = frame_interval_plots(result, taken);
  return {std::move(plots), std::move(frame_plots)};
}

}  // namespace fovlab::analysis::report_detail
