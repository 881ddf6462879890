#pragma once
// The frames `fovlab prerender CONFIG` renders, in its order (shard I/N takes every N-th from the
// I-th), shared with `fovlab slurm prerender`, which sizes its job array by them.
#include <string>
#include <vector>

#include "protocols/stimuli/stimulus_settings.h"

namespace fovlab::app {

// Every path-traced frame the config's stimuli show. InputError naming the config when it does not
// parse, no session could run it, or it has no path-traced stimuli.
std::vector<PathTraceFrameJob> prerender_frame_jobs(const std::string& config_path);

}  // namespace fovlab::app
