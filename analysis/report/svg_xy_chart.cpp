#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <string>
#include <vector>

#include "analysis/report/svg_chart.h"
#include "analysis/report/svg_drawing.h"

namespace fovlab::analysis {

using namespace svg_detail;

namespace {

constexpr double kLegendWidth = 236.0;  // right-hand column for the legend, when there is one
constexpr double kLegendRow = 18.0;
constexpr std::size_t kLegendChars = 36;  // longer labels are cut (the whole label is the entry's <title>)

constexpr std::array<const char*, 3> kBandPalette = {"#888888", "#56B4E9", "#E69F00"};

// The first `limit` characters of a UTF-8 label (never cutting a multi-byte character), with "…"
// appended when something was cut.
std::string shorten(const std::string& text, std::size_t limit) {
  std::size_t characters = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if ((byte & 0xC0) == 0x80) continue;  // continuation byte
    if (characters == limit) return text.substr(0, i) + "\xE2\x80\xA6";
    ++characters;
  }
  return text;
}

const char* series_colour(std::size_t index) { return kPalette[index % (kPalette.size() - 1)]; }  // yellow never
const char* band_colour(std::size_t index) { return kBandPalette[index % kBandPalette.size()]; }

// A point marker centred on (x, y): circle, square, triangle, diamond by series index, so the series
// differ in shape as well as colour.
std::string marker(std::size_t index, double x, double y, const char* colour, bool small = false) {
  const double k = small ? 0.55 : 1.0;  // small markers: about half the size, half transparent
  const std::string fill = std::string(" fill=\"") + colour + "\"" + (small ? " fill-opacity=\"0.5\"" : "");
  switch (index % 4) {
    case 0:
      return "<circle" + attr("cx", x) + attr("cy", y) + attr("r", 4.0 * k) + fill + "/>\n";
    case 1:
      return "<rect" + attr("x", x - 3.5 * k) + attr("y", y - 3.5 * k) + attr("width", 7.0 * k) +
             attr("height", 7.0 * k) + fill + "/>\n";
    case 2:
      return "<polygon points=\"" + coord(x) + "," + coord(y - 5 * k) + " " + coord(x + 4.5 * k) + "," +
             coord(y + 3.5 * k) + " " + coord(x - 4.5 * k) + "," + coord(y + 3.5 * k) + "\"" + fill + "/>\n";
    default:
      return "<polygon points=\"" + coord(x) + "," + coord(y - 5 * k) + " " + coord(x + 5 * k) + "," + coord(y) + " " +
             coord(x) + "," + coord(y + 5 * k) + " " + coord(x - 5 * k) + "," + coord(y) + "\"" + fill + "/>\n";
  }
}

struct LegendEntry {
  std::string label;
  enum class Kind { points, line, bars, band, vertical } kind = Kind::points;
  std::size_t index = 0;  // the palette index of its marker shape
  const char* colour = kPalette[0];
  bool small = false;  // points: the series' small markers
};

std::string draw_legend(const std::vector<LegendEntry>& entries, double left, double top, double bottom) {
  if (entries.empty()) return "";
  std::string out = "<g font-size=\"11\">\n";
  const auto capacity = static_cast<std::size_t>(std::max(1.0, std::floor((bottom - top) / kLegendRow)));
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const double y = top + kLegendRow * static_cast<double>(i) + 9;
    if (i + 1 == capacity && entries.size() > capacity) {
      out += text_at(left, y + 4, "+ " + std::to_string(entries.size() - i) + " more", "start");
      break;
    }
    const LegendEntry& entry = entries[i];
    out += "<g><title>" + xml_escape(entry.label) + "</title>\n";
    switch (entry.kind) {
      case LegendEntry::Kind::points:
        out += marker(entry.index, left + 10, y, entry.colour, entry.small);
        break;
      case LegendEntry::Kind::line:
        out += "<line" + attr("x1", left) + attr("y1", y) + attr("x2", left + 20) + attr("y2", y) + " stroke=\"" +
               entry.colour + "\" stroke-width=\"2\"/>\n";
        break;
      case LegendEntry::Kind::bars:
        out += "<rect" + attr("x", left + 4) + attr("y", y - 5) + attr("width", 12.0) + attr("height", 10.0) +
               " fill=\"" + entry.colour + "\"/>\n";
        break;
      case LegendEntry::Kind::band:
        out += "<rect" + attr("x", left + 2) + attr("y", y - 6) + attr("width", 16.0) + attr("height", 12.0) +
               " fill=\"" + entry.colour + "\" fill-opacity=\"0.3\"/>\n";
        break;
      case LegendEntry::Kind::vertical:
        out += "<line" + attr("x1", left + 10) + attr("y1", y - 7) + attr("x2", left + 10) + attr("y2", y + 7) +
               " stroke=\"" + entry.colour + "\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>\n";
        break;
    }
    out += text_at(left + 26, y + 4, shorten(entry.label, kLegendChars), "start");
    out += "</g>\n";
  }
  out += "</g>\n";
  return out;
}

std::string error_bar(const Frame& frame, double x, double lower, double upper, const char* colour) {
  if (!usable(x) || !usable(lower) || !usable(upper) || x < frame.x.lo || x > frame.x.hi) return "";
  const double cx = frame.px(x);
  const double y1 = frame.py(std::min(lower, upper));
  const double y2 = frame.py(std::max(lower, upper));
  std::string out = std::string("<g stroke=\"") + colour + "\" stroke-width=\"1.2\">";
  out += "<line" + attr("x1", cx) + attr("y1", y1) + attr("x2", cx) + attr("y2", y2) + "/>";
  out += "<line" + attr("x1", cx - 3) + attr("y1", y1) + attr("x2", cx + 3) + attr("y2", y1) + "/>";
  out += "<line" + attr("x1", cx - 3) + attr("y1", y2) + attr("x2", cx + 3) + attr("y2", y2) + "/>";
  return out + "</g>\n";
}

std::size_t point_count(const XySeries& series) { return std::min(series.x.size(), series.y.size()); }

bool has_error_bars(const XySeries& series) {
  const std::size_t n = point_count(series);
  return n > 0 && series.y_lower.size() >= n && series.y_upper.size() >= n;
}

// Bar geometry shared by every bar series: the width of one group of bars in data units (80 % of the
// smallest gap between distinct x values, or 0.8 with a single x value).
double bar_group_width(const std::vector<XySeries>& series) {
  std::vector<double> xs;
  for (const XySeries& s : series) {
    if (s.style != XySeries::Style::bars) continue;
    for (std::size_t i = 0; i < point_count(s); ++i) {
      if (usable(s.x[i]) && usable(s.y[i])) xs.push_back(s.x[i]);
    }
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t i = 1; i < xs.size(); ++i) gap = std::min(gap, xs[i] - xs[i - 1]);
  if (!std::isfinite(gap) || !(gap > 0.0)) gap = 1.0;
  return 0.8 * gap;
}

// The chart on a log10 x axis: every x (points, band ends, vertical lines, fixed bounds) replaced by its log10;
// x <= 0 becomes NaN (left out).
XyChart to_log_x(XyChart chart) {
  const auto log_x = [](double x) { return x > 0.0 ? std::log10(x) : std::numeric_limits<double>::quiet_NaN(); };
  for (XySeries& series : chart.series)
    for (double& x : series.x) x = log_x(x);
  for (XBand& band : chart.bands) {
    band.x_lower = log_x(band.x_lower);
    band.x_upper = log_x(band.x_upper);
  }
  for (XLine& line : chart.vertical_lines) line.x = log_x(line.x);
  if (chart.x_min) chart.x_min = log_x(*chart.x_min);
  if (chart.x_max) chart.x_max = log_x(*chart.x_max);
  chart.x_log = false;
  return chart;
}

// Ticks of a log10 axis over [lo, hi] (log10 units): 1, 2, 5 x 10^k inside, or only 10^k when
// those are more than 10, or every integer multiple when fewer than 3.
std::vector<double> log_ticks(double lo, double hi) {
  const auto ticks_of = [&](std::initializer_list<double> mantissas) {
    std::vector<double> ticks;
    for (int k = int(std::floor(lo)) - 1; k <= int(std::ceil(hi)) + 1 && ticks.size() < 60; ++k)
      for (double m : mantissas) {
        const double t = k + std::log10(m);
        if (t >= lo - 1e-9 && t <= hi + 1e-9) ticks.push_back(t);
      }
    return ticks;
  };
  std::vector<double> ticks = ticks_of({1, 2, 5});
  if (ticks.size() > 10) ticks = ticks_of({1});
  if (ticks.size() < 3) ticks = ticks_of({1, 2, 3, 4, 5, 6, 7, 8, 9});
  return ticks;
}

}  // namespace

std::string render_xy_chart_svg(const XyChart& requested) {
  const XyChart chart = requested.x_log ? to_log_x(requested) : requested;
  // Data extents: every finite point, error bar end, band edge and reference line; bars reach 0.
  Extent x_extent;
  Extent y_extent;
  bool any_data = false;
  const double group_width = bar_group_width(chart.series);
  for (const XySeries& series : chart.series) {
    const bool bars = series.style == XySeries::Style::bars;
    const bool errors = has_error_bars(series);
    for (std::size_t i = 0; i < point_count(series); ++i) {
      if (!usable(series.x[i]) || !usable(series.y[i])) continue;
      any_data = true;
      x_extent.add(series.x[i]);
      y_extent.add(series.y[i]);
      if (bars) {
        x_extent.add(series.x[i] - group_width / 2);
        x_extent.add(series.x[i] + group_width / 2);
        y_extent.add(0.0);
      }
      if (errors && series.style != XySeries::Style::line) {
        y_extent.add(series.y_lower[i]);
        y_extent.add(series.y_upper[i]);
      }
    }
  }
  for (const XBand& band : chart.bands) {
    if (usable(band.x_lower) && usable(band.x_upper)) {
      any_data = true;
      x_extent.add(band.x_lower);
      x_extent.add(band.x_upper);
    }
  }
  for (double line : chart.horizontal_lines) y_extent.add(line);
  for (const XLine& line : chart.vertical_lines) x_extent.add(line.x);

  const auto band_fill = [&](std::size_t i) {
    return chart.bands[i].colour ? series_colour(*chart.bands[i].colour) : band_colour(i);
  };
  const auto line_colour = [](const XLine& line) { return line.colour ? series_colour(*line.colour) : "#333333"; };
  std::vector<LegendEntry> legend;
  for (std::size_t i = 0; i < chart.series.size(); ++i) {
    const XySeries& series = chart.series[i];
    if (series.label.empty()) continue;
    const auto kind = series.style == XySeries::Style::points ? LegendEntry::Kind::points
                      : series.style == XySeries::Style::line ? LegendEntry::Kind::line
                                                              : LegendEntry::Kind::bars;
    const std::size_t index = series.colour.value_or(i);
    legend.push_back({series.label, kind, index, series_colour(index), series.small});
  }
  for (std::size_t i = 0; i < chart.bands.size(); ++i) {
    if (!chart.bands[i].label.empty())
      legend.push_back({chart.bands[i].label, LegendEntry::Kind::band, i, band_fill(i)});
  }
  for (const XLine& line : chart.vertical_lines) {
    if (!line.label.empty()) legend.push_back({line.label, LegendEntry::Kind::vertical, 0, line_colour(line)});
  }

  Frame frame;
  if (!legend.empty()) frame.right = kWidth - kLegendWidth;
  frame.x = make_axis(x_extent, chart.x_min, chart.x_max, false);
  frame.y = make_axis(y_extent, chart.y_min, chart.y_max, false);
  if (requested.x_log) {
    frame.x.log = true;
    frame.x.ticks = log_ticks(frame.x.lo, frame.x.hi);
  }

  std::string out = svg_open(chart.title);
  out += draw_axes(frame, chart.x_label, chart.y_label);

  // Bands under everything else.
  for (std::size_t i = 0; i < chart.bands.size(); ++i) {
    const XBand& band = chart.bands[i];
    if (!usable(band.x_lower) || !usable(band.x_upper)) continue;
    const double x1 = frame.px(std::min(band.x_lower, band.x_upper));
    const double x2 = frame.px(std::max(band.x_lower, band.x_upper));
    out += "<rect" + attr("x", x1) + attr("y", frame.top) + attr("width", std::max(x2 - x1, 1.0)) +
           attr("height", frame.bottom - frame.top) + " fill=\"" + band_fill(i) + "\" fill-opacity=\"" +
           (band.colour ? "0.18" : "0.3") + "\"/>\n";
  }
  for (double line : chart.horizontal_lines) {
    if (!usable(line) || line < frame.y.lo || line > frame.y.hi) continue;
    out += "<line" + attr("x1", frame.left) + attr("y1", frame.py(line)) + attr("x2", frame.right) +
           attr("y2", frame.py(line)) + " stroke=\"#555555\" stroke-width=\"1.2\" stroke-dasharray=\"6 4\"/>\n";
  }
  for (const XLine& line : chart.vertical_lines) {
    const double x = line.x;
    if (!usable(x) || x < frame.x.lo || x > frame.x.hi) continue;
    out += "<line" + attr("x1", frame.px(x)) + attr("y1", frame.top) + attr("x2", frame.px(x)) +
           attr("y2", frame.bottom) + " stroke=\"" + line_colour(line) +
           "\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>\n";
  }

  std::size_t bar_series = 0;
  for (const XySeries& series : chart.series) bar_series += series.style == XySeries::Style::bars ? 1 : 0;
  std::size_t bar_rank = 0;
  for (std::size_t s = 0; s < chart.series.size(); ++s) {
    const XySeries& series = chart.series[s];
    const std::size_t palette_index = series.colour.value_or(s);
    const char* colour = series_colour(palette_index);
    const std::size_t n = point_count(series);
    const bool errors = has_error_bars(series);
    switch (series.style) {
      case XySeries::Style::line: {
        // One polyline per run of finite points; a lone point shows as a dot.
        std::vector<std::pair<double, double>> run;
        auto flush = [&] {
          if (run.size() == 1) {
            out += "<circle" + attr("cx", run[0].first) + attr("cy", run[0].second) + attr("r", 2.5) + " fill=\"" +
                   colour + "\"/>\n";
          } else if (run.size() > 1) {
            out += "<polyline fill=\"none\" stroke=\"" + std::string(colour) + "\" stroke-width=\"2\" points=\"";
            for (std::size_t i = 0; i < run.size(); ++i) {
              // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string&&.
              if (i) out += ' ';
              out += coord(run[i].first);
              out += ',';
              out += coord(run[i].second);
            }
            out += "\"/>\n";
          }
          run.clear();
        };
        for (std::size_t i = 0; i < n; ++i) {
          if (usable(series.x[i]) && usable(series.y[i])) {
            run.emplace_back(frame.px(series.x[i]), frame.py(series.y[i]));
          } else {
            flush();
          }
        }
        flush();
        break;
      }
      case XySeries::Style::points: {
        const bool labelled = series.point_labels.size() >= n;
        for (std::size_t i = 0; i < n; ++i) {
          if (!frame.inside(series.x[i], series.y[i])) continue;
          if (errors) out += error_bar(frame, series.x[i], series.y_lower[i], series.y_upper[i], colour);
          out += marker(palette_index, frame.px(series.x[i]), frame.py(series.y[i]), colour, series.small);
          if (labelled && !series.point_labels[i].empty()) {
            out += text_at(frame.px(series.x[i]) + 6, frame.py(series.y[i]) - 5, series.point_labels[i], "start",
                           " font-size=\"9\" fill=\"#444444\"");
          }
        }
        break;
      }
      case XySeries::Style::bars: {
        const double width = group_width / static_cast<double>(bar_series);
        const double base = std::clamp(0.0, frame.y.lo, frame.y.hi);
        for (std::size_t i = 0; i < n; ++i) {
          if (!usable(series.x[i]) || !usable(series.y[i])) continue;
          const double x0 = series.x[i] - group_width / 2 + width * static_cast<double>(bar_rank);
          const double left = frame.px(x0);
          const double right = frame.px(x0 + width);
          const double top = std::min(frame.py(series.y[i]), frame.py(base));
          const double bottom = std::max(frame.py(series.y[i]), frame.py(base));
          out += "<rect" + attr("x", left) + attr("y", top) + attr("width", std::max(right - left, 0.5)) +
                 attr("height", bottom - top) + " fill=\"" + colour + "\"/>\n";
          if (errors) out += error_bar(frame, x0 + width / 2, series.y_lower[i], series.y_upper[i], "#333333");
        }
        ++bar_rank;
        break;
      }
    }
  }
  if (!any_data) out += no_data_note(frame);
  out += draw_legend(legend, frame.right + 14, frame.top, frame.bottom);
  out += "</svg>\n";
  return out;
}

}  // namespace fovlab::analysis
