#pragma once
// The flags of Ye et al. 2022's sampling models (rmfr, hyperbolic, linear, kfr) for `render` and `bench`:
// sigma, RMFR's focal shares, KFR's alpha, the hyperbolic and linear radii, pixel sizes and p_min,
// --equalise. Their descriptions start with "Sampling:" so a command can refuse them for other
// methods. The display and gaze come from the display flags (app/foveation_flags.h's defaults).
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "foveation/sampling_map.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab::app {

// `focal_shares`: false leaves --fx and --fy to the command (bench takes lists of them).
void add_sampling_flags(CLI::App& command, SamplingSettings& settings, bool focal_shares = true);
std::vector<std::string> given_sampling_only_flags(const CLI::App& command);
// InputError for the first of the `given` sampling flags that none of `models` uses ("--alpha: rmfr
// does not use it; it is kfr's"), as a config refuses a key its method does not have.
void refuse_flags_unused_by(const std::vector<std::string>& given, const std::vector<SamplingModel>& models);

// The map of `model` for the frame the foveation settings describe (their display and gaze; no
// gaze: the centre). InputError naming the flag on bad values.
SamplingMap parse_sampling(SamplingModel model, const SamplingSettings& settings, const FoveationSettings& foveation);

// The flags that reproduce a model's settings, for reports ("--sigma 2.6 --fx 0.3 --fy 0.3"), numbers
// as given.
std::string sampling_flags_text(SamplingModel model, const SamplingSettings& settings);
// The flags of every one of `models`, each once, for a sweep over several (a flag none of them uses
// is left out: bench refuses it); `focal_shares`: --fx and --fy as the sweep had them ("--fx
// 0.05,0.3 --fy 0.3"; empty: the settings'). Numbers as given, so the command reproduces the sweep.
std::string all_sampling_flags_text(const SamplingSettings& settings, const std::vector<SamplingModel>& models,
                                    const std::string& focal_shares = "");

// One line on what the map really samples: "rmfr: 14.8 % of pixels shaded (theoretical speed-up
// 6.76, effective 6.76), mean density 0.148".
std::string sampling_summary(const SamplingMap& map);

}  // namespace fovlab::app
