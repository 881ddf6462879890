// Volume studies end to end (Bruder et al. 2019): a tiny 2AFC study of the full raycast (volume) against the
// Voronoi-foveated one (fvolume) over the sampling density's radius runs headless with the simulated
// observer, with attention checks, replays --verify (fvolume's images depend on each refresh's gaze
// and on the temporal smoothing's history), also with a forged Voronoi cache beside it, and analyzes; bad input is one line with exit code 2: an
// SDF scene for a volume method, a volume reference with a sphere-traced test.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "foveation/voronoi_reconstruction.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "study/schedule/study_plan.h"
#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run_in;
using fovlab::cli_test::write_file;

fs::path working_dir(const std::string& name) {
  return fovlab::cli_test::fresh_folder(fovlab::cli_test::scratch("fovlab-volume-study-cli"), name);
}

std::string volume_config(const std::string& name, const std::string& scene = "shepp-logan",
                          const std::string& test_method = "fvolume") {
  return "[study]\nname = \"" + name +
         "\"\nseed = 33\n\n"
         "[display]\nwidth_px = 40\nheight_px = 30\nrefresh_hz = 60\ndiagonal_in = 27\nviewing_distance_mm = 500\n\n"
         "[stimulus]\nduration_s = 0.1\nframes_per_second = 20\n\n"
         "[stimulus.reference]\nmethod = \"volume\"\n\n"
         "[stimulus.test]\nmethod = \"" +
         test_method +
         "\"\n\n"
         "[levels]\nparameter = \"density_sigma_deg\"\nvalues = [0.5, 3.0]\nhigher_is_better = true\n\n"
         "[protocol]\nkind = \"2afc\"\nquestion = \"same\"\nrepeats = 2\n\n"
         "[attention]\nshare = 0.3\nbreak_s = 1\nmax_errors = 3\n\n"
         "[timing]\nblack_interval_s = 0.05\ninter_trial_s = 0.05\n\n"
         "[[block]]\nscene = \"" +
         scene + "\"\n";
}

TEST(VolumeStudyCli, FoveatedVolumeStudyRunsReplaysAndAnalyzes) {
  const std::string name = "tiny_fvolume";
  const fs::path dir = working_dir(name);
  write_file(dir / "study.toml", volume_config(name));
  const CommandResult session =
      run_in(dir, "run study.toml --participant next --headless --observer simulated:threshold=1.5 --results results");
  ASSERT_EQ(session.exit_code, 0) << session.out << session.err;
  const fs::path log = dir / "results" / name / "P001" / "events.jsonl";
  const std::string text = read_all(log);
  EXPECT_NE(text.find("\"method\":\"fvolume\""), std::string::npos);
  EXPECT_NE(text.find("\"method\":\"volume\""), std::string::npos);
  EXPECT_NE(text.find("session_end"), std::string::npos) << "the session finished";
  EXPECT_FALSE(fs::exists(dir / "stimuli" / "cache" / "voronoi")) << "a session makes its masks, and caches none";

  // A forged Voronoi cache for each level: the weights of every pixel given to its heaviest
  // neighbour (another reconstruction), the reach and the file's hash recomputed, so the file passes
  // every check of its own bytes. Neither a session nor a replay reads the cache: the replay makes
  // the masks as the session did, and matches (it read the forged file, and did not, before).
  const fovlab::StudyConfig config =
      fovlab::parse_study_config_file((dir / "study.toml").string(), fovlab::renderer_scene_catalog());
  int forged = 0;
  for (const fovlab::PlannedStimulus& stimulus : fovlab::make_study_plan(config, "P001").stimuli) {
    if (stimulus.spec.method() != fovlab::RenderMethod::foveated_volume_raycast) continue;
    const fovlab::VoronoiMaskSettings settings = fovlab::voronoi_mask_settings(stimulus.spec);
    fovlab::VoronoiReconstruction made = fovlab::make_voronoi_reconstruction(settings);
    for (size_t pixel = 0; pixel < made.neighbour_weights.size(); pixel += fovlab::kVoronoiNeighbours) {
      made.neighbour_weights[pixel] = 65535;
      for (int k = 1; k < fovlab::kVoronoiNeighbours; ++k) made.neighbour_weights[pixel + size_t(k)] = 0;
    }
    made.neighbour_reach_px = fovlab::voronoi_neighbour_reach_px(made);
    const fs::path file = fovlab::voronoi_cache_file(settings, fovlab::voronoi_cache_folder(dir / "stimuli" / "cache"));
    fs::create_directories(file.parent_path());
    write_file(file, fovlab::voronoi_cache_bytes(made));
    bool made_anew = true;
    const fovlab::VoronoiReconstruction cached =
        fovlab::cached_voronoi_reconstruction(settings, file.parent_path(), {}, &made_anew);
    ASSERT_FALSE(made_anew) << "the forgery passes the cache's own checks";
    ASSERT_EQ(cached.neighbour_weights, made.neighbour_weights);
    ++forged;
  }
  ASSERT_EQ(forged, 2);

  const CommandResult replay = run_in(dir, "replay --verify " + log.string());
  EXPECT_EQ(replay.exit_code, 0) << replay.out << replay.err;
  EXPECT_NE(replay.out.find("replay matches the log"), std::string::npos) << replay.out;

  const CommandResult analysis = run_in(dir, "analyze " + (dir / "results" / name).string());
  EXPECT_EQ(analysis.exit_code, 0) << analysis.out << analysis.err;
  EXPECT_NE(analysis.out.find("study " + name), std::string::npos) << analysis.out;
}

TEST(VolumeStudyCli, ScenesAndMethodsOfAnotherKindAreRefused) {
  const fs::path dir = working_dir("kinds");
  write_file(dir / "sdf.toml", volume_config("tiny_sdf", "primitives"));
  expect_one_line_error(run_in(dir, "validate sdf.toml"), "expected a volume scene");
  std::string mixed = volume_config("tiny_mixed", "shepp-logan", "gt");
  mixed.replace(mixed.find("parameter = \"density_sigma_deg\"\nvalues = [0.5, 3.0]"),
                std::string("parameter = \"density_sigma_deg\"\nvalues = [0.5, 3.0]").size(),
                "parameter = \"max_steps\"\nvalues = [4, 8]");
  write_file(dir / "mixed.toml", mixed);
  expect_one_line_error(run_in(dir, "validate mixed.toml"), "expected a volume method (volume or fvolume)");
  EXPECT_FALSE(fs::exists(dir / "results"));
}

}  // namespace
