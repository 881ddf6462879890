#include "protocols/gaze/gaze_spec.h"

#include <charconv>
#include <optional>
#include <stdexcept>
#include <string_view>

#include "core/input_error.h"
#include "core/prng.h"
#include "protocols/gaze/pupil_gaze_source.h"
#include "protocols/gaze/synthetic_gaze_source.h"
#include "protocols/gaze/trace_gaze_source.h"

namespace fovlab {

namespace {

[[noreturn]] void bad_spec(const std::string& text) {
  throw InputError("--gaze: expected mouse, trace:FILE, synthetic[:seed=N] or pupil:HOST:PORT, got \"" + text +
                   "\"");
}

template <typename T>
bool parse_whole(std::string_view text, T& value) {
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

}  // namespace

GazeSpec parse_gaze_spec(const std::string& text) {
  const std::string_view view(text);
  const auto after = [&](std::string_view prefix) -> std::optional<std::string_view> {
    if (view.substr(0, prefix.size()) != prefix) return std::nullopt;
    return view.substr(prefix.size());
  };

  GazeSpec spec;
  if (view == "mouse") {
    spec.kind = GazeSpec::Kind::mouse;
  } else if (const auto path = after("trace:")) {
    if (path->empty()) bad_spec(text);
    spec.kind = GazeSpec::Kind::trace;
    spec.trace_path = std::string(*path);
  } else if (view == "synthetic") {
    spec.kind = GazeSpec::Kind::synthetic;
  } else if (const auto seed = after("synthetic:seed=")) {
    if (!parse_whole(*seed, spec.seed)) bad_spec(text);  // decimal digits only: no sign, no spaces
    spec.kind = GazeSpec::Kind::synthetic;
    spec.seed_given = true;
  } else if (view == "pupil") {
    spec.kind = GazeSpec::Kind::pupil;
  } else if (const auto address = after("pupil:")) {
    spec.kind = GazeSpec::Kind::pupil;
    const size_t colon = address->rfind(':');
    spec.host = std::string(address->substr(0, colon));
    if (colon != std::string_view::npos) {
      if (!parse_whole(address->substr(colon + 1), spec.port) || spec.port < 1 || spec.port > 65535) bad_spec(text);
    }
    if (spec.host.empty() || spec.host.find(':') != std::string::npos) bad_spec(text);
  } else {
    bad_spec(text);
  }
  return spec;
}

std::unique_ptr<GazeSource> make_gaze_source(const GazeSpec& spec, int width_px, int height_px,
                                             uint64_t session_seed) {
  switch (spec.kind) {
    case GazeSpec::Kind::mouse:
      throw std::logic_error("make_gaze_source: the mouse gaze source is made by the session from its presenter");
    case GazeSpec::Kind::trace:
      return std::make_unique<TraceGazeSource>(spec.trace_path);
    case GazeSpec::Kind::synthetic: {
      SyntheticGazeParams params;
      params.seed = spec.seed_given ? spec.seed : derive_seed(session_seed, "gaze");
      return std::make_unique<SyntheticGazeSource>(params, width_px, height_px);
    }
    case GazeSpec::Kind::pupil: {
      PupilGazeOptions options;
      options.host = spec.host;
      options.port = spec.port;
      return std::make_unique<PupilGazeSource>(options, width_px, height_px);
    }
  }
  throw std::logic_error("make_gaze_source: unknown gaze kind");
}

}  // namespace fovlab
