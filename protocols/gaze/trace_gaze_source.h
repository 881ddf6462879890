#pragma once
// Recorded gaze replayed from a CSV file.
//
// Format: a header line `time_s,x_px,y_px` or `time_s,x_px,y_px,valid`, then one sample a line.
// - time_s: session seconds, finite, non-decreasing (equal times are allowed; the later line wins),
//   at most kMaxGazeTraceTimeS from 0 either way.
// - x_px, y_px: screen pixels (origin top-left, y down). An empty field means the tracker had no
//   position (invalid, "no_data"); `nan`/`inf` mean invalid, "not_finite". The position is not
//   checked against the screen here (the source does not know the screen): sanitize_gaze does it.
// - valid (optional): 1 or 0; 0 marks a blink (invalid, "blink", takes precedence over the above).
// Blank lines are skipped; Windows line ends, spaces around fields and a UTF-8 byte-order mark at
// the start are accepted. Invalid samples without a position have x_px = y_px = 0.
// Limits: a regular file (not a directory, device or FIFO) of at most kMaxGazeTraceBytes (a trace
// of 1000 Hz for two hours is about 200 MB), lines of at most kMaxGazeTraceLineBytes (a sample
// needs some 40).
//
// sample(t) is a step function, not an interpolation: it returns the last sample (as recorded,
// with its own time_s, also its acquired_s) whose time_s <= t; before the first sample it returns
// the first sample.
// A query is a binary search, O(log n).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "protocols/gaze/gaze_source.h"

namespace fovlab {

constexpr uint64_t kMaxGazeTraceBytes = uint64_t(256) << 20;  // 256 MiB
// The furthest a sample's time may be from the session's start, in seconds (11.6 days; a trace is
// at most hours): a sample's age when shown (session time - time_s, in ms in the log and the
// latency report) then stays finite and exact to well under a microsecond. 1e308 made it -inf.
constexpr double kMaxGazeTraceTimeS = 1e6;
constexpr size_t kMaxGazeTraceLineBytes = 1024;

// Parses the CSV text of a gaze trace. `name` (normally the path) starts every error message:
// InputError("name:LINE: field: what was expected, got ..."), one line (what it quotes is cut
// short and its control characters escaped). Throws when there is no sample, and for text over
// the limits above.
std::vector<GazeSample> parse_gaze_trace(std::string_view text, const std::string& name);

class TraceGazeSource final : public GazeSource {
 public:
  // Reads and parses the whole file now; InputError when it cannot be read or is malformed.
  explicit TraceGazeSource(std::string path);

  GazeSample sample(double time_s) override;  // std::invalid_argument for a non-finite time
  std::string describe() const override;      // "trace:<path>"

  const std::vector<GazeSample>& samples() const { return samples_; }

 private:
  std::string path_;
  std::vector<GazeSample> samples_;  // time_s non-decreasing, at least one
};

}  // namespace fovlab
