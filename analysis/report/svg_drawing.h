#pragma once
// Internals of svg_chart.h shared by its chart kinds (svg_xy_chart.cpp, svg_histogram.cpp,
// svg_heat_map.cpp): the canvas, coordinates as text, axes with nice ticks, the data-to-canvas
// frame, the document's opening and the axes drawn. svg_chart.cpp defines them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "analysis/report/svg_chart.h"

namespace fovlab::analysis::svg_detail {

// Canvas (the viewBox; the width and height attributes say the same, so the plots read at 720x420).
inline constexpr double kWidth = 720.0;
inline constexpr double kHeight = 420.0;
inline constexpr double kMarginTop = 44.0;
inline constexpr double kMarginBottom = 58.0;
inline constexpr double kMarginLeft = 72.0;
inline constexpr double kMarginRight = 20.0;
inline constexpr double kInset = 10.0;  // the data keep this far from the axes: edge markers show whole

// Okabe & Ito (2008), "Color Universal Design": distinguishable with every common colour-vision
// deficiency. Yellow (#F0E442) is last: it is faint on white.
inline constexpr std::array<const char*, 8> kPalette = {"#0072B2", "#D55E00", "#009E73", "#CC79A7",
                                                        "#E69F00", "#56B4E9", "#000000", "#F0E442"};

// Values beyond this magnitude are treated as non-finite: they would overflow the axis arithmetic.
inline constexpr double kLargest = 1e300;

inline bool usable(double value) { return std::isfinite(value) && std::fabs(value) <= kLargest; }

// A coordinate with two decimals; never "-0.00", never "nan" (callers only pass finite values, and a
// stray non-finite one is written as 0 rather than break the document).
std::string coord(double value);
// ` name="value"`, the value as coord writes it.
std::string attr(const char* name, double value);

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
Axis make_axis(Extent data, std::optional<double> fixed_lo, std::optional<double> fixed_hi, bool integer_steps);

// A tick label with enough significant digits to tell neighbouring ticks apart.
std::string tick_label(double value, double step);

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

// The document's opening: the <svg> element, its <title>, a white background and the title drawn.
std::string svg_open(const std::string& title);

std::string text_at(double x, double y, const std::string& text, const char* anchor, const char* extra = "");

// Grid lines, the axis frame, ticks with labels and the axis labels.
std::string draw_axes(const Frame& frame, const std::string& x_label, const std::string& y_label);

// "no data", mid-frame.
std::string no_data_note(const Frame& frame);

}  // namespace fovlab::analysis::svg_detail
