#pragma once
// The --gaze option of the command line: where a session's gaze comes from.
//   mouse               the window's cursor (made by the session from its presenter, not here)
//   trace:FILE          a recorded CSV trace (trace_gaze_source.h)
//   synthetic           a random fixation pattern seeded from the session seed
//   synthetic:seed=N    ... with an explicit seed (decimal, 0..2^64-1)
//   synthetic:age_ms=A  ... whose samples are A ms old when read (0..10000; imitates a tracker's
//                       latency); with a seed: synthetic:seed=N,age_ms=A (options in any order)
//   pupil               Pupil Core on 127.0.0.1:50020
//   pupil:HOST:PORT     Pupil Core's Pupil Remote at HOST:PORT (pupil:HOST alone means port 50020)
//   pupil...,surface=NAME,min_confidence=C
//                       the Surface Tracker surface that covers the screen (default "screen") and the
//                       lowest confidence a sample may have (default 0.6, in [0, 1]); docs/gaze.md
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "protocols/gaze/gaze_source.h"
#include "study/config/study_config.h"

namespace fovlab {

struct GazeSpec {
  enum class Kind { mouse, trace, synthetic, pupil, openxr };  // openxr: a headset's eye tracker
  Kind kind = Kind::mouse;
  std::string trace_path;          // trace
  std::string host = "127.0.0.1";  // pupil
  int port = 50020;                // pupil
  std::string surface = "screen";  // pupil: the Surface Tracker surface covering the screen
  double min_confidence = 0.6;     // pupil: samples below it are invalid ("low_confidence")
  uint64_t seed = 0;               // synthetic, when seed_given
  bool seed_given = false;         // synthetic: false = derive_seed(session seed, "gaze")
  double age_ms = 0.0;             // synthetic: how old each sample is when read
};

// The kind of source a spec makes: pupil is a tracker (study_config.h GazeSourceKind).
GazeSourceKind source_kind(const GazeSpec& spec);

// The source a session runs with, and whether --gaze named it.
struct ChosenGaze {
  GazeSpec spec;
  bool requested = false;  // given with --gaze (false: the default)
};

// The source of --gaze `option` ("" for the default) for a session of `config`, headless or in a
// window (docs/gaze.md, "Which source a session may use"). In a headset ([display] kind = "openxr")
// the default is its eye tracker (openxr), or synthetic where [gaze] require leaves trackers out, and
// `openxr` names it in no other session. Headless, the default is synthetic. In a
// window it is the mouse, except for a gaze-contingent study (is_gaze_contingent) or a config whose
// [gaze] require leaves the mouse out: those need --gaze (a tracker: pupil...; the mouse only by
// name, --gaze mouse, a rehearsal), and without it are refused. A source of a kind the config's
// require leaves out is refused, headless too. InputError, one line, naming what to give.
ChosenGaze choose_gaze(const StudyConfig& config, const std::string& option, bool headless);

// The session clock (seconds) as the session reads it: the Pupil source maps the tracker's time
// onto it at start-up. Empty: a monotonic clock of the process (fine for sources that need none).
using SessionClock = std::function<double()>;

// InputError("--gaze: expected mouse, trace:FILE, synthetic[:seed=N], pupil[:HOST[:PORT]][,surface=NAME]
// [,min_confidence=C] or openxr, got \"...\"");
// InputError("--gaze: age_ms: expected milliseconds 0..10000, got \"...\"") for a bad age.
GazeSpec parse_gaze_spec(const std::string& text);

// The source of a trace, synthetic or pupil spec for a screen of width_px x height_px (the pupil one
// connects now, so it may throw InputError). std::logic_error for mouse: the session makes that one
// from its window presenter.
std::unique_ptr<GazeSource> make_gaze_source(const GazeSpec& spec, int width_px, int height_px, uint64_t session_seed,
                                             SessionClock session_clock = {});

}  // namespace fovlab
