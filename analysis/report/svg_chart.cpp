#include "analysis/report/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "analysis/report/svg_drawing.h"
#include "core/number_text.h"

namespace fovlab::analysis::svg_detail {
namespace {

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

}  // namespace

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

std::string svg_open(const std::string& title) {
  const std::string width = format_number(kWidth, 6), height = format_number(kHeight, 6);
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 " + width + " " + height + "\" width=\"" +
                    width + "\" height=\"" + height + "\"";
  out += " font-family=\"sans-serif\" font-size=\"12\" role=\"img\">\n";
  out += "<title>" + xml_escape(title) + "</title>\n";
  out += "<rect x=\"0\" y=\"0\" width=\"" + width + "\" height=\"" + height + "\" fill=\"#ffffff\"/>\n";
  out += "<text" + attr("x", kWidth / 2) + attr("y", 26) +
         " text-anchor=\"middle\" font-size=\"15\" font-weight=\"bold\">" + xml_escape(title) + "</text>\n";
  return out;
}

std::string text_at(double x, double y, const std::string& text, const char* anchor, const char* extra) {
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
  out += "<line" + attr("x1", frame.left) + attr("y1", frame.bottom) + attr("x2", frame.right) +
         attr("y2", frame.bottom) + "/>\n";
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
  for (double tick : frame.y.ticks)
    out += text_at(frame.left - 8, frame.py(tick) + 4, tick_label(tick, frame.y.step), "end");
  if (!x_label.empty())
    out += text_at((frame.left + frame.right) / 2, kHeight - 14, x_label, "middle", " font-size=\"13\"");
  if (!y_label.empty()) {
    const double cy = (frame.top + frame.bottom) / 2;
    out += "<text" + attr("x", 18) + attr("y", cy) +
           " text-anchor=\"middle\" font-size=\"13\" transform=\"rotate(-90 18 " + coord(cy) + ")\">" +
           xml_escape(y_label) + "</text>\n";
  }
  return out;
}

std::string no_data_note(const Frame& frame) {
  return text_at((frame.left + frame.right) / 2, (frame.top + frame.bottom) / 2, "no data", "middle",
                 " fill=\"#777777\" font-size=\"14\"");
}

}  // namespace fovlab::analysis::svg_detail

namespace fovlab::analysis {

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
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

}  // namespace fovlab::analysis
