#include "analysis/report/svg_chart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/number_text.h"

namespace fovlab::analysis {
namespace {

// Canvas (the viewBox; the width and height attributes say the same, so the plots read at 720x420).
constexpr double kWidth = 720.0;
constexpr double kHeight = 420.0;
constexpr double kMarginTop = 44.0;
constexpr double kMarginBottom = 58.0;
constexpr double kMarginLeft = 72.0;
constexpr double kMarginRight = 20.0;
constexpr double kLegendWidth = 236.0;    // right-hand column for the legend, when there is one
constexpr double kInset = 10.0;           // the data keep this far from the axes: edge markers show whole
constexpr double kLegendRow = 18.0;
constexpr std::size_t kLegendChars = 36;  // longer labels are cut (the whole label is the entry's <title>)

// Okabe & Ito (2008), "Color Universal Design": distinguishable with every common colour-vision
// deficiency. Yellow (#F0E442) is last: it is faint on white.
constexpr std::array<const char*, 8> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                 "#E69F00", "#56B4E9", "#000000", "#F0E442"};
constexpr std::array<const char*, 3> kBandPalette = {"#888888", "#56B4E9", "#E69F00"};

// Viridis (matplotlib, perceptually uniform, colour-blind safe) at 9 evenly spaced stops; colours
// between the stops are interpolated linearly in sRGB.
constexpr std::array<std::array<int, 3>, 9> kViridis = {{{68, 1, 84},
                                                         {71, 44, 122},
                                                         {59, 81, 139},
                                                         {44, 113, 142},
                                                         {33, 144, 141},
                                                         {39, 173, 129},
                                                         {92, 200, 99},
                                                         {170, 220, 50},
                                                         {253, 231, 37}}};

// Values beyond this magnitude are treated as non-finite: they would overflow the axis arithmetic.
constexpr double kLargest = 1e300;

bool usable(double value) { return std::isfinite(value) && std::fabs(value) <= kLargest; }

// A coordinate with two decimals; never "-0.00", never "nan" (callers only pass finite values, and a
// stray non-finite one is written as 0 rather than break the document).
std::string coord(double value) {
  if (!std::isfinite(value)) value = 0.0;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f", value);
  std::string result = text;
  if (result == "-0.00") result = "0.00";
  return result;
}

std::string attr(const char* name, double value) { return std::string(" ") + name + "=\"" + coord(value) + "\""; }

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

// ---- axes ------------------------------------------------------------------------------------

// 1, 2 or 5 times a power of ten, near span / target.
double nice_step(double span, int target) {
  const double raw = span / target;
  if (!(raw > 0.0) || !std::isfinite(raw)) return 1.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  const double fraction = raw / magnitude;
  const double nice = fraction <= 1.0 ? 1.0 : fraction <= 2.0 ? 2.0 : fraction <= 5.0 ? 5.0 : 10.0;
  return nice * magnitude;
}

struct Axis {
  double lo = 0.0;
  double hi = 1.0;
  double step = 0.2;
  std::vector<double> ticks;
  bool log = false;  // positions and ticks are log10 of the values; labels are the values
};

// The finite extent of some values (lo > hi while there is none).
struct Extent {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double value) {
    if (!usable(value)) return;
    lo = std::min(lo, value);
    hi = std::max(hi, value);
  }
  bool empty() const { return lo > hi; }
};

// The axis for the data extent, or for the caller's bounds where given. Sides the caller did not fix
// are rounded out to a multiple of the tick step, so the ticks cover the data; a zero-width range is
// padded; with no data at all the range is [0, 1].
Axis make_axis(Extent data, std::optional<double> fixed_lo, std::optional<double> fixed_hi, bool integer_steps) {
  const bool has_lo = fixed_lo && usable(*fixed_lo);
  const bool has_hi = fixed_hi && usable(*fixed_hi);
  if (data.empty()) {
    data.lo = 0.0;
    data.hi = 1.0;
  }
  double lo = has_lo ? *fixed_lo : data.lo;
  double hi = has_hi ? *fixed_hi : data.hi;
  if (has_lo && has_hi && lo > hi) std::swap(lo, hi);
  if (has_lo && !has_hi && hi < lo) hi = lo;
  if (has_hi && !has_lo && lo > hi) lo = hi;
  const double magnitude = std::max(std::fabs(lo), std::fabs(hi));
  if (hi - lo <= magnitude * 1e-12) {  // all equal: pad around the value
    const double pad = integer_steps ? 1.0 : (magnitude > 0.0 ? magnitude * 0.1 : 1.0);
    if (has_lo && has_hi) {  // both bounds fixed to one value: widen both
      lo -= pad;
      hi += pad;
    } else {  // widen the free side(s)
      if (!has_lo) lo -= pad;
      if (!has_hi) hi += pad;
    }
  }
  double step = nice_step(hi - lo, 5);
  if (integer_steps) step = std::max(1.0, std::round(step));
  if (!has_lo) lo = std::floor(lo / step) * step;
  if (!has_hi) hi = std::ceil(hi / step) * step;
  if (!(hi > lo)) hi = lo + step;
  Axis axis;
  axis.lo = lo;
  axis.hi = hi;
  axis.step = step;
  const double first = std::ceil(lo / step - 1e-9);
  const double last = std::floor(hi / step + 1e-9);
  for (double i = first; i <= last && axis.ticks.size() < 50; i += 1.0) {
    double tick = i * step;
    if (std::fabs(tick) < step * 1e-9) tick = 0.0;
    axis.ticks.push_back(tick);
  }
  return axis;
}

// A tick label with enough significant digits to tell neighbouring ticks apart (at least 6, as "%g";
// trailing zeros are dropped, so 0.30000000000000004 reads "0.3").
std::string tick_label(double value, double step) {
  const double largest = std::max(std::fabs(value), step);
  const int digits = static_cast<int>(std::ceil(std::log10(largest)) - std::floor(std::log10(step))) + 1;
  return format_number(value, std::clamp(digits, 6, 15));
}

// The data-to-canvas mapping of a plot rectangle.
struct Frame {
  double left = kMarginLeft;
  double top = kMarginTop;
  double right = kWidth - kMarginRight;
  double bottom = kHeight - kMarginBottom;
  Axis x;
  Axis y;

  double px(double value) const {
    const double t = (std::clamp(value, x.lo, x.hi) - x.lo) / (x.hi - x.lo);
    return left + kInset + t * (right - left - 2 * kInset);
  }
  double py(double value) const {
    const double t = (std::clamp(value, y.lo, y.hi) - y.lo) / (y.hi - y.lo);
    return bottom - kInset - t * (bottom - top - 2 * kInset);
  }
  bool inside(double xv, double yv) const {
    return usable(xv) && usable(yv) && xv >= x.lo && xv <= x.hi && yv >= y.lo && yv <= y.hi;
  }
};

std::string svg_open(const std::string& title) {
  const std::string width = format_number(kWidth, 6), height = format_number(kHeight, 6);
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " + width + " " + height + "\" width=\"" +
                    width + "\" height=\"" + height + "\"";
  out += " font-family=\"sans-serif\" font-size=\"12\" role=\"img\">\n";
  out += "<title>" + xml_escape(title) + "</title>\n";
  out += "<rect x=\"0\" y=\"0\" width=\"" + width + "\" height=\"" + height + "\" fill=\"#ffffff\"/>\n";
  out += "<text" + attr("x", kWidth / 2) + attr("y", 26) + " text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" +
         xml_escape(title) + "</text>\n";
  return out;
}

std::string text_at(double x, double y, const std::string& text, const char* anchor, const char* extra = "") {
  return "<text" + attr("x", x) + attr("y", y) + " text-anchor=\"" + anchor + "\"" + extra + ">" + xml_escape(text) +
         "</text>\n";
}

// Grid lines, the axis frame, ticks with labels and the axis labels.
std::string draw_axes(const Frame& frame, const std::string& x_label, const std::string& y_label) {
  std::string out = "<g stroke=\"#e5e5e5\" stroke-width=\"1\">\n";
  for (double tick : frame.x.ticks) {
    out += "<line" + attr("x1", frame.px(tick)) + attr("y1", frame.top) + attr("x2", frame.px(tick)) +
           attr("y2", frame.bottom) + "/>\n";
  }
  for (double tick : frame.y.ticks) {
    out += "<line" + attr("x1", frame.left) + attr("y1", frame.py(tick)) + attr("x2", frame.right) +
           attr("y2", frame.py(tick)) + "/>\n";
  }
  out += "</g>\n";
  out += "<g stroke=\"#333333\" stroke-width=\"1\">\n";
  out += "<line" + attr("x1", frame.left) + attr("y1", frame.bottom) + attr("x2", frame.right) + attr("y2", frame.bottom) +
         "/>\n";
  out += "<line" + attr("x1", frame.left) + attr("y1", frame.top) + attr("x2", frame.left) + attr("y2", frame.bottom) +
         "/>\n";
  for (double tick : frame.x.ticks) {
    out += "<line" + attr("x1", frame.px(tick)) + attr("y1", frame.bottom) + attr("x2", frame.px(tick)) +
           attr("y2", frame.bottom + 5) + "/>\n";
  }
  for (double tick : frame.y.ticks) {
    out += "<line" + attr("x1", frame.left - 5) + attr("y1", frame.py(tick)) + attr("x2", frame.left) +
           attr("y2", frame.py(tick)) + "/>\n";
  }
  out += "</g>\n";
  for (double tick : frame.x.ticks)
    out += text_at(frame.px(tick), frame.bottom + 18,
                   frame.x.log ? format_number(std::pow(10.0, tick), 4) : tick_label(tick, frame.x.step), "middle");
  for (double tick : frame.y.ticks) out += text_at(frame.left - 8, frame.py(tick) + 4, tick_label(tick, frame.y.step), "end");
  if (!x_label.empty()) out += text_at((frame.left + frame.right) / 2, kHeight - 14, x_label, "middle", " font-size=\"13\"");
  if (!y_label.empty()) {
    const double cy = (frame.top + frame.bottom) / 2;
    out += "<text" + attr("x", 18) + attr("y", cy) + " text-anchor=\"middle\" font-size=\"13\" transform=\"rotate(-90 18 " +
           coord(cy) + ")\">" + xml_escape(y_label) + "</text>\n";
  }
  return out;
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
      return "<rect" + attr("x", x - 3.5 * k) + attr("y", y - 3.5 * k) + attr("width", 7.0 * k) + attr("height", 7.0 * k) +
             fill + "/>\n";
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
  bool small = false;     // points: the series' small markers
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
        out += "<rect" + attr("x", left + 4) + attr("y", y - 5) + attr("width", 12.0) + attr("height", 10.0) + " fill=\"" +
               entry.colour + "\"/>\n";
        break;
      case LegendEntry::Kind::band:
        out += "<rect" + attr("x", left + 2) + attr("y", y - 6) + attr("width", 16.0) + attr("height", 12.0) + " fill=\"" +
               entry.colour + "\" fill-opacity=\"0.3\"/>\n";
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

std::string no_data_note(const Frame& frame) {
  return text_at((frame.left + frame.right) / 2, (frame.top + frame.bottom) / 2, "no data", "middle",
                 " fill=\"#777777\" font-size=\"14\"");
}

// A valid printf format for one double: literal text, "%%", and exactly one conversion
// %[flags][width][.precision](f|F|e|E|g|G|a|A) with width and precision of at most two digits.
bool valid_cell_format(const std::string& format) {
  int conversions = 0;
  for (std::size_t i = 0; i < format.size(); ++i) {
    if (format[i] != '%') continue;
    ++i;
    if (i < format.size() && format[i] == '%') continue;
    while (i < format.size() && std::string("-+ #0").find(format[i]) != std::string::npos) ++i;
    std::size_t digits = 0;
    while (i < format.size() && format[i] >= '0' && format[i] <= '9') ++i, ++digits;
    if (digits > 2) return false;
    if (i < format.size() && format[i] == '.') {
      ++i;
      digits = 0;
      while (i < format.size() && format[i] >= '0' && format[i] <= '9') ++i, ++digits;
      if (digits > 2) return false;
    }
    if (i >= format.size() || std::string("fFeEgGaA").find(format[i]) == std::string::npos) return false;
    ++conversions;
  }
  return conversions == 1;
}

std::string format_cell(const std::string& format, double value) {
  char text[160];
  // The format was checked by valid_cell_format: one floating-point conversion, bounded width.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
  std::snprintf(text, sizeof text, format.c_str(), value);
#pragma GCC diagnostic pop
  return text;
}

std::string rgb_text(double r, double g, double b) {
  char text[16];
  std::snprintf(text, sizeof text, "#%02x%02x%02x", static_cast<int>(std::lround(r)), static_cast<int>(std::lround(g)),
                static_cast<int>(std::lround(b)));
  return text;
}

// Viridis at t in [0, 1]; also whether the colour is dark (then the text on it is white).
std::string viridis(double t, bool* dark) {
  t = std::clamp(std::isfinite(t) ? t : 0.5, 0.0, 1.0);
  const double position = t * static_cast<double>(kViridis.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(position), kViridis.size() - 2);
  const double f = position - static_cast<double>(i);
  double rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = kViridis[i][c] + f * (kViridis[i + 1][c] - kViridis[i][c]);
  if (dark) *dark = t < 0.55;
  return rgb_text(rgb[0], rgb[1], rgb[2]);
}

}  // namespace

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default:
        // Control characters other than tab, newline and carriage return are not allowed in XML 1.0.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n' && c != '\r') {
          out += ' ';
        } else {
          out += c;
        }
    }
  }
  return out;
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
    if (!chart.bands[i].label.empty()) legend.push_back({chart.bands[i].label, LegendEntry::Kind::band, i, band_fill(i)});
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
    out += "<line" + attr("x1", frame.px(x)) + attr("y1", frame.top) + attr("x2", frame.px(x)) + attr("y2", frame.bottom) +
           " stroke=\"" + line_colour(line) + "\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>\n";
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
            out += "<circle" + attr("cx", run[0].first) + attr("cy", run[0].second) + attr("r", 2.5) + " fill=\"" + colour +
                   "\"/>\n";
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

std::string render_histogram_svg(const Histogram& histogram) {
  // Each usable value with its weight (1, or its entry of `counts`).
  std::vector<double> values;
  std::vector<double> weights;
  const bool weighted = histogram.counts.size() == histogram.values.size();
  for (std::size_t i = 0; i < histogram.values.size(); ++i) {
    if (!usable(histogram.values[i])) continue;
    double weight = weighted ? histogram.counts[i] : 1.0;
    if (!usable(weight) || weight < 0.0) weight = 0.0;
    values.push_back(histogram.values[i]);
    weights.push_back(std::round(weight));
  }
  std::vector<double> edges;
  for (double edge : histogram.bin_edges) {
    if (usable(edge)) edges.push_back(edge);
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  if (edges.size() < 2) {  // no usable bins: one bin over the data (or [0, 1])
    Extent extent;
    for (double value : values) extent.add(value);
    if (extent.empty()) extent = {0.0, 1.0};
    if (!(extent.hi > extent.lo)) extent = {extent.lo - 0.5, extent.hi + 0.5};
    edges = {extent.lo, extent.hi};
  }
  std::vector<uint64_t> counts(edges.size() - 1, 0);
  for (std::size_t v = 0; v < values.size(); ++v) {
    // Values below the first edge count in the first bin, at or above the last edge in the last.
    const auto upper = std::upper_bound(edges.begin(), edges.end(), values[v]);
    std::size_t bin = upper == edges.begin() ? 0 : static_cast<std::size_t>(upper - edges.begin()) - 1;
    bin = std::min(bin, counts.size() - 1);
    counts[bin] += static_cast<uint64_t>(weights[v]);
  }
  const uint64_t most = counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());

  Frame frame;
  Extent x_extent;
  x_extent.add(edges.front());
  x_extent.add(edges.back());
  Extent y_extent;
  y_extent.add(0.0);
  y_extent.add(static_cast<double>(std::max<uint64_t>(most, 1)));
  frame.x = make_axis(x_extent, std::nullopt, std::nullopt, false);
  frame.y = make_axis(y_extent, 0.0, std::nullopt, true);

  std::string out = svg_open(histogram.title);
  out += draw_axes(frame, histogram.x_label, "count");
  for (std::size_t i = 0; i < counts.size(); ++i) {
    if (counts[i] == 0) continue;
    const double x1 = frame.px(edges[i]);
    const double x2 = frame.px(edges[i + 1]);
    const double y = frame.py(static_cast<double>(counts[i]));
    out += "<rect" + attr("x", x1) + attr("y", y) + attr("width", std::max(x2 - x1, 0.5)) +
           attr("height", frame.py(0.0) - y) + " fill=\"" + kPalette[0] + "\" stroke=\"#ffffff\" stroke-width=\"1\"/>\n";
    // Without count labels, a bar too short to see (under 3 px) still gets its count: a rare late
    // frame must not vanish beside a tall bar.
    if (histogram.count_labels || frame.py(0.0) - y < 3.0)
      out += text_at((x1 + x2) / 2, y - 4, std::to_string(counts[i]), "middle", " font-size=\"11\"");
  }
  bool marked = false;
  for (double line : histogram.vertical_lines) {
    if (!usable(line) || line < frame.x.lo || line > frame.x.hi) continue;
    marked = true;
    out += "<line" + attr("x1", frame.px(line)) + attr("y1", frame.top) + attr("x2", frame.px(line)) +
           attr("y2", frame.bottom) + " stroke=\"" + kPalette[1] + "\" stroke-width=\"2\" stroke-dasharray=\"4 3\"/>\n";
  }
  if (marked && !histogram.vertical_lines_label.empty())
    out += text_at(frame.right - 4, frame.top + 14, histogram.vertical_lines_label, "end",
                   (std::string(" font-size=\"11\" fill=\"") + kPalette[1] + "\"").c_str());
  if (values.empty()) out += no_data_note(frame);
  out += "</svg>\n";
  return out;
}

std::string render_heat_map_svg(const HeatMap& map) {
  const std::size_t columns = map.x_values.size();
  const std::size_t rows = map.y_values.size();
  const std::string format = valid_cell_format(map.cell_format) ? map.cell_format : "%.2f";
  auto cell = [&](std::size_t row, std::size_t column) {
    const std::size_t index = row * columns + column;
    return index < map.cells.size() && usable(map.cells[index]) ? map.cells[index]
                                                                 : std::numeric_limits<double>::quiet_NaN();
  };
  Extent values;
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns; ++c) values.add(cell(r, c));
  }
  // A fixed colour scale replaces the data's extent on the side(s) it gives.
  {
    const bool fixed_lo = map.colour_min && usable(*map.colour_min);
    const bool fixed_hi = map.colour_max && usable(*map.colour_max);
    if (!(fixed_lo && fixed_hi && *map.colour_min > *map.colour_max) && !values.empty()) {
      if (fixed_lo) values.lo = *map.colour_min;
      if (fixed_hi) values.hi = *map.colour_max;
      if (values.lo > values.hi) values.hi = values.lo;  // one bound fixed beyond every value
    }
  }

  Frame frame;
  frame.right = kWidth - 110.0;  // the colour bar and its labels
  std::string out = svg_open(map.title);
  if (rows == 0 || columns == 0) {
    out += no_data_note(frame);
    out += "</svg>\n";
    return out;
  }
  const double cell_width = (frame.right - frame.left) / static_cast<double>(columns);
  const double cell_height = (frame.bottom - frame.top) / static_cast<double>(rows);
  const bool write_values = cell_width >= 30.0 && cell_height >= 14.0;
  const double font = std::min(11.0, cell_height * 0.6);
  const double span = values.empty() ? 0.0 : values.hi - values.lo;
  auto position = [&](double value) { return span > 0.0 ? std::clamp((value - values.lo) / span, 0.0, 1.0) : 0.5; };

  // Row 0 at the bottom, as on a y axis.
  for (std::size_t r = 0; r < rows; ++r) {
    const double y = frame.bottom - cell_height * static_cast<double>(r + 1);
    for (std::size_t c = 0; c < columns; ++c) {
      const double x = frame.left + cell_width * static_cast<double>(c);
      const double value = cell(r, c);
      bool dark = false;
      const std::string fill = std::isnan(value) ? "#dddddd" : viridis(position(value), &dark);
      out += "<rect" + attr("x", x) + attr("y", y) + attr("width", cell_width) + attr("height", cell_height) + " fill=\"" +
             fill + "\" stroke=\"#ffffff\" stroke-width=\"1\"/>\n";
      if (write_values && !std::isnan(value)) {
        out += "<text" + attr("x", x + cell_width / 2) + attr("y", y + cell_height / 2 + font * 0.35) +
               " text-anchor=\"middle\"" + attr("font-size", font) + " fill=\"" + (dark ? "#ffffff" : "#000000") + "\">" +
               xml_escape(format_cell(format, value)) + "</text>\n";
      }
    }
  }
  // Marked cells: a black outline with a white one inside, visible on every viridis colour.
  for (std::size_t index : map.marked_cells) {
    if (index >= rows * columns) continue;
    const double x = frame.left + cell_width * static_cast<double>(index % columns);
    const double y = frame.bottom - cell_height * static_cast<double>(index / columns + 1);
    out += "<rect" + attr("x", x + 2) + attr("y", y + 2) + attr("width", std::max(cell_width - 4, 1.0)) +
           attr("height", std::max(cell_height - 4, 1.0)) + " fill=\"none\" stroke=\"#000000\" stroke-width=\"3\"/>\n";
    out += "<rect" + attr("x", x + 4.5) + attr("y", y + 4.5) + attr("width", std::max(cell_width - 9, 1.0)) +
           attr("height", std::max(cell_height - 9, 1.0)) + " fill=\"none\" stroke=\"#ffffff\" stroke-width=\"1.5\"/>\n";
  }
  if (!map.marked_label.empty() && !map.marked_cells.empty()) {
    out += text_at(kWidth - 8, kHeight - 14, map.marked_label, "end", " font-size=\"11\"");
  }
  // Row and column labels (every k-th where they would crowd).
  const std::size_t column_stride = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(50.0 / cell_width)));
  for (std::size_t c = 0; c < columns; c += column_stride) {
    if (!usable(map.x_values[c])) continue;
    out += text_at(frame.left + cell_width * (static_cast<double>(c) + 0.5), frame.bottom + 18,
                   format_number(map.x_values[c], 6), "middle");
  }
  const std::size_t row_stride = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(16.0 / cell_height)));
  for (std::size_t r = 0; r < rows; r += row_stride) {
    if (!usable(map.y_values[r])) continue;
    out += text_at(frame.left - 8, frame.bottom - cell_height * (static_cast<double>(r) + 0.5) + 4,
                   format_number(map.y_values[r], 6), "end");
  }
  if (!map.x_label.empty()) {
    out += text_at((frame.left + frame.right) / 2, kHeight - 14, map.x_label, "middle", " font-size=\"13\"");
  }
  if (!map.y_label.empty()) {
    const double cy = (frame.top + frame.bottom) / 2;
    out += "<text" + attr("x", 18) + attr("y", cy) + " text-anchor=\"middle\" font-size=\"13\" transform=\"rotate(-90 18 " +
           coord(cy) + ")\">" + xml_escape(map.y_label) + "</text>\n";
  }

  // Colour bar: 48 stacked steps from the smallest value (bottom) to the largest (top), with ticks.
  if (!values.empty()) {
    const double bar_left = frame.right + 24;
    const double bar_width = 18;
    constexpr int kSteps = 48;
    const double step_height = (frame.bottom - frame.top) / kSteps;
    for (int i = 0; i < kSteps; ++i) {
      const double t = (i + 0.5) / kSteps;
      out += "<rect" + attr("x", bar_left) + attr("y", frame.bottom - step_height * (i + 1)) + attr("width", bar_width) +
             attr("height", step_height + 0.5) + " fill=\"" + viridis(t, nullptr) + "\"/>\n";
    }
    out += "<rect" + attr("x", bar_left) + attr("y", frame.top) + attr("width", bar_width) +
           attr("height", frame.bottom - frame.top) + " fill=\"none\" stroke=\"#333333\" stroke-width=\"1\"/>\n";
    std::vector<double> ticks;
    double step = 1.0;
    if (span > 0.0) {
      const Axis axis = make_axis(values, values.lo, values.hi, false);
      ticks = axis.ticks;
      step = axis.step;
    } else {
      ticks = {values.lo};
      step = std::max(std::fabs(values.lo), 1e-300);
    }
    for (double tick : ticks) {
      const double y = frame.bottom - position(tick) * (frame.bottom - frame.top);
      out += "<line" + attr("x1", bar_left + bar_width) + attr("y1", y) + attr("x2", bar_left + bar_width + 4) +
             attr("y2", y) + " stroke=\"#333333\" stroke-width=\"1\"/>\n";
      out += text_at(bar_left + bar_width + 7, y + 4, tick_label(tick, step), "start", " font-size=\"11\"");
    }
  }
  out += "</svg>\n";
  return out;
}

}  // namespace fovlab::analysis
