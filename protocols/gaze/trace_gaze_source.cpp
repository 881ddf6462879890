#include "protocols/gaze/trace_gaze_source.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  for (;;) {
    const size_t comma = line.find(',');
    fields.push_back(trim(line.substr(0, comma)));
    if (comma == std::string_view::npos) break;
    line.remove_prefix(comma + 1);
  }
  return fields;
}

// The whole field as a number (from_chars: also "nan", "inf", "infinity"); false when it is not one.
bool parse_number(std::string_view field, double& value) {
  if (!field.empty() && field.front() == '+') field.remove_prefix(1);
  if (field.empty()) return false;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  return error == std::errc() && end == field.data() + field.size();
}

class LineError {
 public:
  LineError(const std::string& name, size_t line) : prefix_(name + ":" + std::to_string(line) + ": ") {}
  [[noreturn]] void fail(const std::string& what) const { throw InputError(prefix_ + what); }

 private:
  std::string prefix_;
};

}  // namespace

std::vector<GazeSample> parse_gaze_trace(std::string_view text, const std::string& name) {
  if (text.size() > kMaxGazeTraceBytes)
    throw InputError(name + ": " + std::to_string(text.size()) + " bytes: expected a gaze trace of at most " +
                     byte_size_text(kMaxGazeTraceBytes));
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);  // UTF-8 byte order mark

  std::vector<GazeSample> samples;
  size_t column_count = 0;  // 0 until the header was read
  size_t line_number = 0;
  while (!text.empty()) {
    const size_t newline = text.find('\n');
    const std::string_view line = text.substr(0, newline);
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    ++line_number;
    const LineError error(name, line_number);
    if (line.size() > kMaxGazeTraceLineBytes)
      error.fail("a line of " + std::to_string(line.size()) + " bytes: expected at most " +
                 std::to_string(kMaxGazeTraceLineBytes) + " (time_s,x_px,y_px[,valid])");
    if (trim(line).empty()) continue;

    const std::vector<std::string_view> fields = split_fields(line);
    if (column_count == 0) {
      const bool base = fields.size() >= 3 && fields[0] == "time_s" && fields[1] == "x_px" && fields[2] == "y_px";
      if (base && fields.size() == 3) {
        column_count = 3;
      } else if (base && fields.size() == 4 && fields[3] == "valid") {
        column_count = 4;
      } else {
        error.fail("expected the header \"time_s,x_px,y_px\" or \"time_s,x_px,y_px,valid\", got " +
                   quoted_input(trim(line)));
      }
      continue;
    }

    if (fields.size() != column_count) {
      error.fail("expected " + std::to_string(column_count) + " comma-separated fields (" +
                 (column_count == 3 ? "time_s,x_px,y_px" : "time_s,x_px,y_px,valid") + "), got " +
                 std::to_string(fields.size()));
    }

    GazeSample sample;
    if (!parse_number(fields[0], sample.time_s)) {
      error.fail("time_s: expected a number, got " + quoted_input(fields[0]));
    }
    if (!std::isfinite(sample.time_s)) {
      error.fail("time_s: expected a finite number, got " + quoted_input(fields[0]));
    }
    if (std::abs(sample.time_s) > kMaxGazeTraceTimeS) {
      error.fail("time_s: expected seconds on the session clock from " + exact_number_text(-kMaxGazeTraceTimeS) +
                 " to " + exact_number_text(kMaxGazeTraceTimeS) + " (11.6 days), got " + quoted_input(fields[0]));
    }
    if (!samples.empty() && sample.time_s < samples.back().time_s) {
      error.fail("time_s: " + exact_number_text(sample.time_s) + " is earlier than the previous sample (" +
                 exact_number_text(samples.back().time_s) + ")");
    }

    static constexpr const char* axis_names[2] = {"x_px", "y_px"};
    double position[2] = {0.0, 0.0};
    bool missing = false;
    bool not_finite = false;
    for (int axis = 0; axis < 2; ++axis) {
      const std::string_view field = fields[1 + axis];
      if (field.empty()) {
        missing = true;
        continue;
      }
      double value = 0.0;
      if (!parse_number(field, value)) {
        error.fail(std::string(axis_names[axis]) + ": expected a number, an empty field or nan, got " +
                   quoted_input(field));
      }
      if (std::isfinite(value)) {
        position[axis] = value;
      } else {
        not_finite = true;
      }
    }

    bool blink = false;
    if (column_count == 4) {
      if (fields[3] == "0") {
        blink = true;
      } else if (fields[3] != "1") {
        error.fail("valid: expected 0 or 1, got " + quoted_input(fields[3]));
      }
    }

    sample.x_px = position[0];
    sample.y_px = position[1];
    if (blink) {
      sample.valid = false;
      sample.invalid_reason = "blink";
    } else if (missing) {
      sample.valid = false;
      sample.invalid_reason = "no_data";
    } else if (not_finite) {
      sample.valid = false;
      sample.invalid_reason = "not_finite";
    }
    if (!sample.valid && (missing || not_finite)) sample.x_px = sample.y_px = 0.0;
    samples.push_back(std::move(sample));
  }

  if (column_count == 0) {
    throw InputError(name +
                     ":1: expected the header \"time_s,x_px,y_px\" or \"time_s,x_px,y_px,valid\", got an empty file");
  }
  if (samples.empty()) throw InputError(name + ": expected at least one gaze sample after the header, got none");
  return samples;
}

TraceGazeSource::TraceGazeSource(std::string path) : path_(std::move(path)) {
  samples_ = parse_gaze_trace(read_input_file(path_, "a gaze trace (.csv)", kMaxGazeTraceBytes), path_);
}

GazeSample TraceGazeSource::sample(double time_s) {
  if (!std::isfinite(time_s)) throw std::invalid_argument("TraceGazeSource::sample: time is not finite");
  // First sample later than time_s; the one before it is in use (or the first before the trace).
  const auto later = std::upper_bound(samples_.begin(), samples_.end(), time_s,
                                      [](double t, const GazeSample& s) { return t < s.time_s; });
  GazeSample sample = later == samples_.begin() ? samples_.front() : *(later - 1);
  sample.acquired_s = sample.time_s;  // the recorded sample's own time
  return sample;
}

std::string TraceGazeSource::describe() const { return "trace:" + path_; }

}  // namespace fovlab
