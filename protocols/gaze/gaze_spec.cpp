#include "protocols/gaze/gaze_spec.h"

#include <charconv>
#include <cmath>
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
  throw InputError(
      "--gaze: expected mouse, trace:FILE, synthetic[:seed=N], "
      "pupil[:HOST[:PORT]][,surface=NAME][,min_confidence=C] or openxr, got \"" +
      text + "\"");
}

template <typename T>
bool parse_whole(std::string_view text, T& value) {
  if (text.empty()) return false;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size();
}

// The options of "synthetic:...": comma-separated seed=N and age_ms=A, each at most once.
void parse_synthetic_options(const std::string& text, std::string_view options, GazeSpec& spec) {
  bool age_given = false;
  while (true) {
    const size_t comma = options.find(',');
    const std::string_view option = options.substr(0, comma);
    if (option.substr(0, 5) == "seed=" && !spec.seed_given) {
      if (!parse_whole(option.substr(5), spec.seed)) bad_spec(text);  // decimal digits only: no sign, no spaces
      spec.seed_given = true;
    } else if (option.substr(0, 7) == "age_ms=" && !age_given) {
      const std::string_view value = option.substr(7);
      if (!parse_whole(value, spec.age_ms) || !std::isfinite(spec.age_ms) || spec.age_ms < 0.0 || spec.age_ms > 10000.0)
        throw InputError("--gaze: age_ms: expected milliseconds 0..10000, got \"" + std::string(value) + "\"");
      age_given = true;
    } else {
      bad_spec(text);
    }
    if (comma == std::string_view::npos) break;
    options.remove_prefix(comma + 1);
  }
}

// The options after "pupil...,": surface=NAME (letters, digits, '_', '-', ' ', '.'; at most 64) and
// min_confidence=C in [0, 1], each at most once.
void parse_pupil_options(const std::string& text, std::string_view options, GazeSpec& spec) {
  bool surface_given = false, confidence_given = false;
  while (true) {
    const size_t comma = options.find(',');
    const std::string_view option = options.substr(0, comma);
    if (option.substr(0, 8) == "surface=" && !surface_given) {
      const std::string_view name = option.substr(8);
      const bool plain = !name.empty() && name.size() <= 64 &&
                         name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-. ") ==
                             std::string_view::npos;
      if (!plain)
        throw InputError(
            "--gaze: surface: expected a Surface Tracker name of 1 to 64 letters, digits, '_', '-', '.' or "
            "spaces, got \"" +
            std::string(name) + "\"");
      spec.surface = std::string(name);
      surface_given = true;
    } else if (option.substr(0, 15) == "min_confidence=" && !confidence_given) {
      const std::string_view value = option.substr(15);
      if (!parse_whole(value, spec.min_confidence) || !(spec.min_confidence >= 0.0 && spec.min_confidence <= 1.0))
        throw InputError("--gaze: min_confidence: expected a number in [0, 1], got \"" + std::string(value) + "\"");
      confidence_given = true;
    } else {
      bad_spec(text);
    }
    if (comma == std::string_view::npos) break;
    options.remove_prefix(comma + 1);
  }
}

// How to give a source of `kind` on the command line.
std::string how_to_give(GazeSourceKind kind) {
  switch (kind) {
    case GazeSourceKind::tracker:
      return "--gaze pupil[:HOST[:PORT]] for the eye tracker";
    case GazeSourceKind::trace:
      return "--gaze trace:FILE for a recorded trace";
    case GazeSourceKind::synthetic:
      return "--gaze synthetic for a simulated gaze";
    case GazeSourceKind::mouse:
      return "--gaze mouse for a rehearsal with the pointer as gaze";
  }
  return "";
}

std::string how_to_give(const std::vector<GazeSourceKind>& kinds) {
  std::string text;
  for (size_t i = 0; i < kinds.size(); ++i)
    text += (i == 0 ? "" : i + 1 == kinds.size() ? " or " : ", ") + how_to_give(kinds[i]);
  return text;
}

// "x.toml:12: gaze.require = tracker"
std::string require_named(const StudyConfig& config) {
  return config.source_path + (config.gaze.require_line > 0 ? ":" + std::to_string(config.gaze.require_line) : "") +
         ": gaze.require = " + config.gaze.require_text();
}

}  // namespace

GazeSourceKind source_kind(const GazeSpec& spec) {
  switch (spec.kind) {
    case GazeSpec::Kind::mouse:
      return GazeSourceKind::mouse;
    case GazeSpec::Kind::trace:
      return GazeSourceKind::trace;
    case GazeSpec::Kind::synthetic:
      return GazeSourceKind::synthetic;
    case GazeSpec::Kind::pupil:
    case GazeSpec::Kind::openxr:
      return GazeSourceKind::tracker;
  }
  return GazeSourceKind::mouse;
}

ChosenGaze choose_gaze(const StudyConfig& config, const std::string& option, bool headless) {
  const GazeConfig& require = config.gaze;
  ChosenGaze chosen;
  const bool in_headset = config.display.kind == DisplayKind::openxr;
  if (!option.empty()) {
    chosen.spec = parse_gaze_spec(option);
    chosen.requested = true;
    const GazeSourceKind kind = source_kind(chosen.spec);
    if (!require.require.empty() && !require.allows(kind))
      throw InputError("--gaze " + option + ": " + require_named(config) + ": expected a source of that kind, got a " +
                       gaze_source_kind_name(kind) + " (give " + how_to_give(require.require) + ")");
    if (chosen.spec.kind == GazeSpec::Kind::openxr && !in_headset)
      throw InputError("--gaze openxr: the headset's eye tracker gives the gaze of a study in a headset ([display] "
                       "kind = \"openxr\"); " + config.source_path + " is not one");
    return chosen;
  }
  if (in_headset && (require.require.empty() || require.allows(GazeSourceKind::tracker))) {
    chosen.spec = parse_gaze_spec("openxr");
    return chosen;
  }
  if (headless || in_headset) {
    chosen.spec = parse_gaze_spec("synthetic");
    if (!require.require.empty() && !require.allows(GazeSourceKind::synthetic))
      throw InputError(require_named(config) + ": a " + (in_headset ? "headset" : "headless") +
                       " session's default gaze is synthetic; give " +
                       how_to_give(require.require));
    return chosen;
  }
  const bool mouse_only = require.require.size() == 1 && require.require.front() == GazeSourceKind::mouse;
  if (mouse_only || (require.require.empty() && !is_gaze_contingent(config))) {
    chosen.spec = parse_gaze_spec("mouse");
    return chosen;
  }
  if (!require.require.empty())
    throw InputError(require_named(config) + ": a session in a window needs its gaze source named; give " +
                     how_to_give(require.require));
  const std::string method(describe(config.stimulus.test.method).depends_on_gaze
                               ? describe(config.stimulus.test.method).name
                               : describe(config.stimulus.reference.method).name);
  throw InputError(config.source_path + ": a gaze-contingent study (" + method +
                   " follows the gaze) in a window needs its gaze source named; give " +
                   how_to_give(GazeSourceKind::tracker) + ", or " + how_to_give(GazeSourceKind::mouse) +
                   " (docs/gaze.md)");
}

GazeSpec parse_gaze_spec(const std::string& text) {
  std::string_view view(text);
  if (view.substr(0, 5) == "pupil" && view.find(',') != std::string_view::npos) {  // pupil options
    GazeSpec spec = parse_gaze_spec(std::string(view.substr(0, view.find(','))));
    if (spec.kind != GazeSpec::Kind::pupil) bad_spec(text);
    parse_pupil_options(text, view.substr(view.find(',') + 1), spec);
    return spec;
  }
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
  } else if (const auto options = after("synthetic:")) {
    parse_synthetic_options(text, *options, spec);
    spec.kind = GazeSpec::Kind::synthetic;
  } else if (view == "openxr") {
    spec.kind = GazeSpec::Kind::openxr;
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

std::unique_ptr<GazeSource> make_gaze_source(const GazeSpec& spec, int width_px, int height_px, uint64_t session_seed,
                                             SessionClock session_clock) {
  switch (spec.kind) {
    case GazeSpec::Kind::mouse:
    case GazeSpec::Kind::openxr:
      throw std::logic_error("make_gaze_source: the mouse and headset gaze sources are made by the session from its "
                             "presenter");
    case GazeSpec::Kind::trace:
      return std::make_unique<TraceGazeSource>(spec.trace_path);
    case GazeSpec::Kind::synthetic: {
      SyntheticGazeParams params;
      params.seed = spec.seed_given ? spec.seed : derive_seed(session_seed, "gaze");
      params.sample_age_ms = spec.age_ms;
      return std::make_unique<SyntheticGazeSource>(params, width_px, height_px);
    }
    case GazeSpec::Kind::pupil: {
      PupilGazeOptions options;
      options.host = spec.host;
      options.port = spec.port;
      options.surface = spec.surface;
      options.min_confidence = spec.min_confidence;
      if (session_clock) options.session_clock = std::move(session_clock);
      return std::make_unique<PupilGazeSource>(options, width_px, height_px);
    }
  }
  throw std::logic_error("make_gaze_source: unknown gaze kind");
}

}  // namespace fovlab
