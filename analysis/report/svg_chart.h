#pragma once
// Plots as SVG text, written by the project (no plotting library): x-y charts (points with error
// bars, lines, bands), histograms and heat maps, with axes, ticks, labels and a legend. The output
// is a complete standalone <svg> document (720x420 viewBox, no XML prolog, no ids, no external
// references) that also embeds in HTML as is. Text is XML-escaped.
//
// Common rules:
// - Axes get "nice" ticks (1, 2 or 5 times a power of ten). A bound the caller does not fix is the
//   data's extent rounded out to a tick, so the ticks always cover the data; a zero-width range is
//   padded. With no data at all the range is [0, 1] and the chart says "no data".
// - Non-finite values (and magnitudes above 1e300) are skipped wherever they appear: no number is
//   ever written as "nan" or "inf".
// - Colours: Okabe-Ito for series (by index, with marker shapes circle, square, triangle, diamond),
//   viridis for heat maps. The output is deterministic: the same input gives the same bytes.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace fovlab::analysis {

struct XySeries {
  enum class Style { points, line, bars };
  std::string label;  // legend entry ("" for none)
  Style style = Style::points;
  std::vector<double> x;
  std::vector<double> y;
  std::vector<double> y_lower;  // error bars (points, bars): empty or one per point (else ignored)
  std::vector<double> y_upper;
  // Points only: a short text drawn beside each point (e.g. the settings of a benchmark cell); empty or
  // one per point (else ignored); "" for none at that point.
  std::vector<std::string> point_labels;
  // The palette index of its colour and marker shape; none: the series' own index. Series of one
  // group (its data, its curve, its threshold) share one.
  std::optional<std::size_t> colour;
  // Points only: small, half-transparent markers (e.g. each participant's, under the pooled ones).
  bool small = false;
};

// A shaded horizontal interval [x_lower, x_upper] (e.g. a threshold's confidence interval).
struct XBand {
  std::string label;
  double x_lower = 0.0;
  double x_upper = 0.0;
  std::optional<std::size_t> colour;  // a series palette index (lighter); none: the band palette by band index
};

// A vertical line across the plot at x (e.g. a threshold), dashed, drawn over the bands and under
// the series.
struct XLine {
  std::string label;  // legend entry ("" for none)
  double x = 0.0;
  std::optional<std::size_t> colour;  // a series palette index; none: dark grey
};

struct XyChart {
  std::string title;
  std::string x_label;
  std::string y_label;
  // Default: the data's range (points, error bars, bands, reference lines; bars reach 0), rounded
  // out to ticks. Points outside a fixed range are not drawn; lines, bars, bands and error
  // bars are clamped to the plot area.
  std::optional<double> x_min, x_max, y_min, y_max;
  // A logarithmic x axis (for log-spaced levels such as 4, 8, ..., 128): positions by log10(x),
  // ticks at 1, 2 and 5 times the powers of ten in range (only the powers when there are many),
  // labelled with their values. Points and band ends at x <= 0 are left out.
  bool x_log = false;
  std::vector<XySeries> series;          // drawn in order, coloured by index
  std::vector<XBand> bands;              // drawn first, under everything else
  std::vector<double> horizontal_lines;  // e.g. 0.5 or a score cutoff, dashed
  std::vector<XLine> vertical_lines;     // counted in the x range like the bands
};

struct Histogram {
  std::string title;
  std::string x_label;         // the y axis counts (integer ticks); each bar is labelled with its count
  std::vector<double> values;  // non-finite values are ignored
  // Ascending, >= 2; values outside are counted in the end bins, a value on an inner edge in the bin
  // above it. Unsorted or repeated edges are sorted and merged; fewer than two usable edges give one
  // bin over the data.
  std::vector<double> bin_edges;
  // Empty, or one per value: how many times each value counts (e.g. values already tallied); a
  // non-finite or negative count counts 0. Else ignored.
  std::vector<double> counts;
  std::vector<double> vertical_lines;  // dashed marks at these x (e.g. a limit), in the x range
  std::string vertical_lines_label;    // what the marks are, written in the top right corner
  bool count_labels = true;            // each bar labelled with its count (false: many narrow bars;
                                       // a bar under 3 px tall is still labelled, so it is not missed)
};

struct HeatMap {
  std::string title;
  std::string x_label;
  std::string y_label;
  std::vector<double> x_values;  // column labels
  std::vector<double> y_values;  // row labels; row 0 is drawn at the bottom, as on a y axis
  // Row-major, y_values.size() * x_values.size() (missing cells and non-finite values are blank
  // grey cells; extra values are ignored). Colours run over viridis from the smallest finite value to
  // the largest, shown by a colour bar.
  std::vector<double> cells;
  // printf format of the number written in each cell (when cells are large enough): one conversion
  // of f, e, g or a (with flags, width and precision of at most two digits each), "%%" and literal
  // text; anything else falls back to "%.2f".
  std::string cell_format = "%.2f";
  // A fixed colour scale (e.g. a rating's 1..3) instead of the data's extent, on either end or both;
  // values beyond it take the end colour. A bound that is not finite, or bounds in the wrong order,
  // are ignored.
  std::optional<double> colour_min, colour_max;
  // Cells outlined in black and white (row-major indices, e.g. the highest mean); indices outside
  // the grid are ignored. `marked_label` (e.g. "outlined: best") is written in the bottom right corner.
  std::vector<std::size_t> marked_cells;
  std::string marked_label;
};

std::string render_xy_chart_svg(const XyChart& chart);
std::string render_histogram_svg(const Histogram& histogram);
std::string render_heat_map_svg(const HeatMap& map);

// "a < b & c" -> "a &lt; b &amp; c" (also " and '); control characters XML 1.0 forbids become
// spaces. Also right for HTML text and attribute values.
std::string xml_escape(const std::string& text);

}  // namespace fovlab::analysis
