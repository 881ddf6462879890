#pragma once
// What several subcommands share on the command line: the Vulkan context they open and the
// tracing flags they accept.
#include <filesystem>
#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "foveation/voronoi_reconstruction.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/context.h"

namespace fovlab::app {

// Context options from --device and the validation default (vk::validation_requested_by_default).
vk::ContextOptions context_options(const std::string& device_selector);

// Throws (exit code 1) when the validation layer reported anything: a clean run is part of the
// contract, and the tests run the command with validation on.
void fail_on_validation_messages(const vk::Context& context);

// Whether a window can be opened: DISPLAY (X11) or WAYLAND_DISPLAY is set.
bool display_available();

// Where the Voronoi sampling masks and their weights are cached (foveation/voronoi_reconstruction.h),
// under the working directory as the pre-render cache is.
inline const std::filesystem::path kVoronoiCacheFolder = voronoi_cache_folder(kDefaultCacheRoot);

// Seconds as "42s", "3m07s" or "2h05m".
std::string duration_text(double seconds);

// A progress report for work measured as a share done (0 to 1): silent for the first second, then on
// a terminal one line rewritten in place ("what: 42 %, ETA 12 s"), otherwise a line every 10 %.
std::function<void(double)> percent_progress(const std::string& what);

// A progress report for work in `total` steps of similar cost: each call (after a step, naming it)
// prints one line to stderr, "what: 3/12 (temple, 16 spp) after 41 s, ETA 2 min", so that lines
// interleave cleanly with a table printed on stdout.
std::function<void(const std::string&)> step_progress(const std::string& what, int total);

// "I/N" with whole numbers 0 <= I < N <= 100000: one of N parts of a job (prerender --shard, bench
// --cells). Bad text is fail_flag naming `flag`; `example` says what I/N means there.
struct PartOfN {
  int index = 0;
  int count = 1;
};
PartOfN parse_part_of_n(const std::string& text, const std::string& flag, const std::string& example);

// --time, --levels, --min-filter, --max-steps, --hit-threshold.
void add_trace_options(CLI::App& command, SphereTraceSettings& settings);

// Which of --min-filter and --coarse-test a parsed command gave (PyramidFlagsGiven and
// with_method_pyramid_defaults: protocols/stimuli/stimulus_settings.h).
using fovlab::PyramidFlagsGiven;
using fovlab::with_method_pyramid_defaults;
PyramidFlagsGiven given_pyramid_flags(const CLI::App& command);

// The flags checked against the method's descriptor first (the ranges and values a study config
// takes: "--max-steps 5000: expected an integer in 1..4096"), then the sphere tracer's
// validate(settings), its SettingError worded with the flag of render and bench that sets the field.
void validate_trace_flags(const SphereTraceSettings& settings);

}  // namespace fovlab::app
