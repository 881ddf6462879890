#pragma once
// The display and gaze flags of the commands that need a physical display (rays, compare):
// --diagonal-in D | --size-mm WxH, --distance-mm D, --gaze X,Y. They are read as text and parsed
// after CLI11, so every error is one line naming the flag and what was expected (exit code 2).
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include <CLI/CLI.hpp>

#include "core/number_text.h"
#include "foveation/display_geometry.h"

namespace fovlab::app {

struct DisplayFlags {
  std::string diagonal_in;
  std::string size_mm;
  std::string distance_mm;
  std::string gaze;
};

// Fills in what `flags` leaves out with Polychronakis et al. 2021's set-up (sections 4.1, 4.3), the default of the
// commands that need a display and are not FIPR's (blend, resample, voronoi, bench-fpt, render and
// bench-volume): a 27-inch 16:9 monitor at 500 mm. Returns what was assumed ("" when nothing was),
// for display_line.
std::string default_to_fpt_study_display(DisplayFlags& flags);

// One line for a command's output saying which display its figures assume, e.g. "display 1280x720
// px, 597.7x336.2 mm at 500 mm, 46.1 px/deg at the centre (assumed: Polychronakis et al. 2021's 27-inch monitor at
// 500 mm; set --diagonal-in or --size-mm, and --distance-mm)"; `assumed` "": the flags gave it.
std::string display_line(const DisplayGeometry& display, const std::string& assumed);

// `required`: the command needs a display (exactly one size flag and the distance); otherwise they
// may all be left out (has_display false).
void add_display_flags(CLI::App& command, DisplayFlags& flags, bool required);
bool has_display(const DisplayFlags& flags);
// The display of width_px x height_px pixels. InputError naming the flag when a value is missing,
// not a positive number, or both or neither of --diagonal-in and --size-mm are given.
DisplayGeometry parse_display(const DisplayFlags& flags, int width_px, int height_px);
// --gaze X,Y in pixels, or each in percent of the frame with a trailing % ("50%,50%" is the centre);
// any finite numbers (off the screen is allowed); empty: the centre.
std::pair<double, double> parse_gaze(const std::string& text, int width_px, int height_px);

// Helpers for other flags given as text.
[[noreturn]] void fail_flag(const std::string& flag, const std::string& expected, const std::string& got);
// "AxB" split at its one separator (any of `separators`); nullopt without exactly one.
std::optional<std::pair<std::string_view, std::string_view>> split_pair(std::string_view text,
                                                                        std::string_view separators);

}  // namespace fovlab::app
