#pragma once
// Deterministic replay of a session from its log alone: the plan is rebuilt from the header (config
// text, participant, seed) and compared with the logged trials; every presented frame is rendered
// again with the logged gaze (a gaze-dependent stimulus: every image of a presentation, in order)
// and compared by hash (same device) or by SSIM >= 0.999 against frames saved on the recording
// device (--reference-frames); a simulated observer's answers are derived again; the event chain is
// checked line by line.
#include <string>
#include <vector>

#include "study/log/log_integrity.h"

namespace fovlab {

struct ReplayOptions {
  std::string log_path;
  std::string frames_out;        // write every re-rendered frame here (PNG): stimulusS_frameF.png, and for
                                 // gaze-dependent stimuli one image a refresh, trialT_stepP_stimulusS_imageI.png;
                                 // a headset session's right eye's with "_right" before ".png"
  std::string reference_frames;  // compare by SSIM with frames another device wrote with frames_out
  double min_ssim = 0.999;
  std::string device_selector;
  bool validation = false;
  int max_differences = 20;                 // the list stops after this many
  std::string lab_key_path;                 // --lab-key: verify the seals' MACs of a keyed log
  std::string cache_dir = "stimuli/cache";  // the pre-render cache (path-traced frames, Voronoi masks)
};

struct ReplayOutcome {
  int trials = 0;
  bool session_ended = false;  // the log has its session_end (completed or excluded)
  LogIntegrity integrity;      // sealed, unsealed or broken
  int presents_checked = 0;    // logged presents whose frame was compared (in a headset, each eye's)
  int frames_rendered = 0;     // distinct frames rendered again
  bool same_device = true;
  std::string comparison;                // "hash" or "ssim"
  double lowest_ssim = 1.0;              // ssim comparison only
  std::vector<std::string> differences;  // the first max_differences, "where: what"
  int difference_count = 0;
  double render_s = 0.0;
  double wall_s = 0.0;
};

ReplayOutcome replay_session(const ReplayOptions& options);

}  // namespace fovlab
