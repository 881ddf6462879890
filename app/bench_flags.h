#pragma once
// fovlab bench's flags: registered on a command (fovlab bench, and fovlab slurm bench's check of the
// flags it passes on), then read and checked into bench's typed options (bench/bench.h), before
// Vulkan is opened: bad input is one InputError naming the flag, and nothing is written.
#include <filesystem>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "app/cli_support.h"
#include "app/foveation_flags.h"
#include "bench/bench.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::app {

// The flags of `fovlab bench` as given (lists still as text where they are parsed by us).
struct BenchFlags {
  std::vector<std::string> scenes{"primitives", "columns", "temple"};
  std::vector<int> spps{1, 4, 16};
  SphereTraceSettings settings;
  int repeats = 5;
  std::filesystem::path json;
  std::filesystem::path out_dir;
  std::string device;
  bool require_gpu = false;
  bool step_breakdown = false;  // --step-breakdown
  std::vector<std::string> methods{"gt", "ipr"};
  // --times: scene times in seconds, comma-separated (e.g. the rotating patterns' angles); empty:
  // --time alone. time_given: --time was on the command line too (refused with --times).
  std::vector<std::string> times;
  bool time_given = false;
  // FIPR sweep (Polychronakis et al. 2023, 5.2: refresh 1, 1/2, 1/4; fovea 2.5 to 15 degrees in steps of 2.5).
  std::vector<std::string> refresh{"1", "2", "4"};
  std::vector<std::string> fovea_deg{"2.5", "5", "7.5", "10", "12.5", "15"};
  FoveationFlags foveation;  // display, gaze and the other FIPR flags; its fovea_deg and refresh are unused
  PyramidFlagsGiven pyramid_flags_given;  // --min-filter, --coarse-test: else each method's own defaults
  // FIPR-only flags the user gave (e.g. "--refresh"): refused unless fipr is among the methods.
  std::vector<std::string> fipr_flags_given;
  SamplingSettings sampling;  // Ye et al. 2022's sampling models (rmfr, hyperbolic, linear, kfr in --methods)
  // RMFR's f_x and f_y as shares of the screen, comma-separated: every pair is a cell (Figure 6's sweep).
  std::vector<std::string> focal_shares_x{"0.3"};
  std::vector<std::string> focal_shares_y{"0.3"};
  std::vector<std::string> sampling_flags_given;
  // --cells I/N: measure only part I of N of the sweep's units (bench/bench_parts.h); empty: all.
  std::string cells;
  // --headset CONFIG (issue 42): a study config with [display] kind = "openxr"; each eye is measured
  // at its size from its head-locked view. --eye left, right or both (a sweep an eye, left first).
  std::string headset;
  std::string eye = "both";
  // The flags given that the headset's config decides (--width, --height, the display's size and
  // distance), and whether --eye was given: refused with --headset, and --eye without it.
  std::vector<std::string> headset_flags_given;
  bool eye_given = false;
};

// Registers bench's flags on `command` (fovlab bench, and fovlab slurm bench's check of the flags it
// passes on to its tasks); after parsing, note_given_bench_flags records which were given.
void add_bench_flags(CLI::App& command, BenchFlags& flags);
void note_given_bench_flags(CLI::App& command, BenchFlags& flags);

// bench's flags as words (as a shell splits them; fovlab slurm bench passes them on so), parsed
// and noted as fovlab bench parses them, not yet checked (read_bench_flags checks them). InputError
// "`what`: CLI11's reason" when they do not parse.
BenchFlags parse_bench_flags(const std::vector<std::string>& words, const std::string& what);

// The flags of a sweep's command as sweep_command writes it ("fovlab bench --scenes ... "), parsed.
// InputError when the text is not such a command.
BenchFlags parse_sweep_command(const std::string& command);

// Checks every flag (lists, ranges, the frame settings of every spp and FIPR variant, the display)
// and returns them typed: the methods, scene times, FIPR variants and sampling models' maps. Throws
// InputError naming the flag.
bench::BenchOptions read_bench_flags(const BenchFlags& flags);
// read_bench_flags, planned (bench::plan_bench).
bench::BenchPlan plan_bench(const BenchFlags& flags);

// read_bench_flags for each eye --eye names (left first): with --headset CONFIG, the eye's size,
// its head-locked view (at -/+ ipd_mm / 2 along the head's x, in metres: a scene unit is a metre,
// docs/hmd.md; the config's asymmetric angles) in settings.eye, the display the eye's off-axis image
// plane (eye_display) for FIPR, the sampling models and the metrics, the gaze at its principal point
// unless --gaze gives one in that eye's pixels. Without --headset, read_bench_flags alone. InputError
// (one line) for a config that is not a headset's or lacks the eyes' size, an --eye other than left,
// right or both, --eye without --headset, and --width, --height, --diagonal-in, --size-mm,
// --distance-mm or --cells with --headset.
std::vector<bench::BenchOptions> read_bench_flags_per_eye(const BenchFlags& flags);

}  // namespace fovlab::app
