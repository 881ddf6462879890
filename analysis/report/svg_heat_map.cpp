#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "analysis/report/svg_chart.h"
#include "analysis/report/svg_drawing.h"
#include "core/number_text.h"

namespace fovlab::analysis {

using namespace svg_detail;

namespace {

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
      out += "<rect" + attr("x", x) + attr("y", y) + attr("width", cell_width) + attr("height", cell_height) +
             " fill=\"" + fill + "\" stroke=\"#ffffff\" stroke-width=\"1\"/>\n";
      if (write_values && !std::isnan(value)) {
        out += "<text" + attr("x", x + cell_width / 2) + attr("y", y + cell_height / 2 + font * 0.35) +
               " text-anchor=\"middle\"" + attr("font-size", font) + " fill=\"" + (dark ? "#ffffff" : "#000000") +
               "\">" + xml_escape(format_cell(format, value)) + "</text>\n";
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
           attr("height", std::max(cell_height - 9, 1.0)) +
           " fill=\"none\" stroke=\"#ffffff\" stroke-width=\"1.5\"/>\n";
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
    out += "<text" + attr("x", 18) + attr("y", cy) +
           " text-anchor=\"middle\" font-size=\"13\" transform=\"rotate(-90 18 " + coord(cy) + ")\">" +
           xml_escape(map.y_label) + "</text>\n";
  }

  // Colour bar: 48 stacked steps from the smallest value (bottom) to the largest (top), with ticks.
  if (!values.empty()) {
    const double bar_left = frame.right + 24;
    const double bar_width = 18;
    constexpr int kSteps = 48;
    const double step_height = (frame.bottom - frame.top) / kSteps;
    for (int i = 0; i < kSteps; ++i) {
      const double t = (i + 0.5) / kSteps;
      out += "<rect" + attr("x", bar_left) + attr("y", frame.bottom - step_height * (i + 1)) +
             attr("width", bar_width) + attr("height", step_height + 0.5) + " fill=\"" + viridis(t, nullptr) + "\"/>\n";
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
