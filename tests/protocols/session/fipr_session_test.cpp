// FIPR stimuli live in sessions and in replay: each refresh of a FIPR presentation is rendered with
// that refresh's gaze and its image index (frame * refreshes + refresh), so the periphery refresh
// reuses the presentation's previous image and every presentation starts afresh; replay renders the
// same images in the same order and gets the same hashes. Small (64x48), short (6 images a
// presentation) and on the primitives scene, so it runs in seconds on lavapipe.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "protocols/stimuli/stimulus_settings.h"
#include "study/log/event_log.h"
#include "study/log/session_record.h"
#include "study/schedule/study_plan.h"
#include "protocols/session/replay.h"
#include "protocols/session/session.h"
#include "protocols/stimuli/stimulus_library.h"
#include "tests/protocols/session/session_test_support.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;
using test::fresh_folder;
using test::read_file;
using test::relabelled_schema;
using test::VulkanTest;
using test::replay;
using test::simulated_on_trace;

// 2AFC, GT against FIPR with the periphery refreshed every 2nd image and taken from the mid level
// (periphery_steps 0, the paper's reading, so the images depend on the gaze), two fovea sizes, 2 repeats:
// 4 trials, each with one FIPR presentation of 2 frames x 3 refreshes = 6 images.
const std::string kFiprStudy = R"([study]
name = "fipr_session"
seed = 5

[display]
width_px = 64
height_px = 48
refresh_hz = 60
width_mm = 240
height_mm = 180
viewing_distance_mm = 300

[stimulus]
duration_s = 0.1
frames_per_second = 20
camera_start_s = 0.5

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "fipr"
periphery_refresh = 2
periphery_steps = 0
mask_seed = 11

[levels]
parameter = "fovea_radius_deg"
values = [2.5, 10]

[protocol]
kind = "2afc"
question = "same"
repeats = 2

[timing]
black_interval_s = 0.05
inter_trial_s = 0.05

[[block]]
scene = "primitives"
)";

StudyConfig fipr_config(const std::string& text = kFiprStudy) {
  // Built-in scenes only: the path is for messages and the log header.
  return parse_study_config_text(text, (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/studies/fipr.toml").string(),
                                 renderer_scene_catalog());
}

// A gaze trace that moves every refresh (a Lissajous path over the frame) for `seconds`, with a
// sample that has no position every 5th refresh (the session shows the last valid one instead), so
// every presentation of 6 refreshes has one.
fs::path moving_trace(const fs::path& folder, double seconds) {
  const fs::path path = folder / "moving.csv";
  std::ofstream out(path);
  out << std::setprecision(17) << "time_s,x_px,y_px\n";
  for (int i = 0; i * (1.0 / 60.0) < seconds; ++i) {
    const double t = i / 60.0;
    if (i % 5 == 4) {
      out << t << ",,\n";
      continue;
    }
    out << t << "," << 32.0 + 28.0 * std::sin(3.1 * t) << "," << 24.0 + 20.0 * std::cos(4.3 * t) << "\n";
  }
  return path;
}

fs::path still_trace(const fs::path& folder) {
  const fs::path path = folder / "still.csv";
  std::ofstream(path) << "time_s,x_px,y_px\n0,20.5,30.25\n";
  return path;
}

// The stimulus events of the log's complete trials that showed a FIPR stimulus.
std::vector<StimulusEvent> fipr_presentations(const std::string& log_path) {
  const SessionRecord record = read_session_record(read_event_log(log_path));
  const auto stimuli = record.header.at("stimuli").get<std::vector<nlohmann::json>>();
  std::vector<StimulusEvent> shown;
  for (const RecordedTrial& trial : record.trials)
    for (const StimulusEvent& event : trial.stimuli)
      if (stimuli.at(static_cast<size_t>(event.stimulus)).at("method") == "fipr") shown.push_back(event);
  return shown;
}

TEST(FiprSession, MovingGazeRendersLiveAndReplaysToTheSameHashes) {
  const fs::path results = fresh_folder("fipr-moving");
  const StudyConfig config = fipr_config();
  const SessionOutcome outcome = run_session(config, simulated_on_trace(results, moving_trace(results, 60.0)));
  ASSERT_TRUE(outcome.finished);
  EXPECT_EQ(outcome.trials_completed, 4);

  // The header's FIPR stimuli carry the display of [display].
  const SessionRecord record = read_session_record(read_event_log(outcome.log_path));
  int fipr_stimuli = 0;
  for (const nlohmann::json& stimulus : record.header.at("stimuli")) {
    if (stimulus.at("method") != "fipr") continue;
    ++fipr_stimuli;
    EXPECT_EQ(stimulus.at("parameters").at("display_width_mm"), 240.0);
    EXPECT_EQ(stimulus.at("parameters").at("display_height_mm"), 180.0);
    EXPECT_EQ(stimulus.at("parameters").at("viewing_distance_mm"), 300.0);
  }
  EXPECT_EQ(fipr_stimuli, 2);

  const std::vector<StimulusEvent> presentations = fipr_presentations(outcome.log_path);
  ASSERT_EQ(presentations.size(), 4u);
  std::set<std::vector<double>> positions;
  int invalid = 0;
  for (const StimulusEvent& shown : presentations) {
    EXPECT_EQ(shown.hash.size(), 6u);
    EXPECT_EQ(shown.frame, std::vector<int>({0, 0, 0, 1, 1, 1}));
    for (const auto& [x, y] : shown.gaze) positions.insert({x, y});
    invalid += static_cast<int>(shown.invalid_gaze.size());
  }
  EXPECT_GT(positions.size(), 12u) << "the gaze moves from refresh to refresh";
  EXPECT_GE(invalid, 4) << "the trace's samples without a position were shown with a held one";

  const ReplayOutcome replayed = replay(outcome.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
  EXPECT_EQ(replayed.trials, 4);
  // Every FIPR image is rendered again (4 x 6), the GT reference's 2 frames once.
  EXPECT_EQ(replayed.frames_rendered, 4 * 6 + 2);
  EXPECT_EQ(replayed.presents_checked, 4 * 6 + 4 * 6);

  // Another gaze for one presentation: replay renders other images and says so.
  const std::string original = read_file(outcome.log_path);
  std::string altered;
  std::istringstream lines(original);
  bool done = false;
  for (std::string line; std::getline(lines, line);) {
    if (!done && line.find("\"event\":\"stimulus\"") != std::string::npos) {
      nlohmann::json event = nlohmann::json::parse(line);
      ASSERT_TRUE(presentations.front().stamp.seq);
      if (event.at("seq") == *presentations.front().stamp.seq) {
        for (nlohmann::json& gaze : event.at("gaze")) gaze = nlohmann::json({63.5, 0.5});
        line = event.dump();
        done = true;
      }
    }
    altered += line + "\n";
  }
  ASSERT_TRUE(done);
  const fs::path altered_path = results / "altered.jsonl";
  std::ofstream(altered_path, std::ios::binary) << altered;
  const ReplayOutcome tampered = replay(altered_path.string());
  bool hash_named = false;
  for (const std::string& difference : tampered.differences)
    hash_named |= difference.find("frame hash") != std::string::npos && difference.find("image") != std::string::npos;
  EXPECT_TRUE(hash_named) << "a changed gaze changes the FIPR images";
}

// Log schemas 5, 6 and 10 brought FIPR's periphery_reconstruction (default bilinear), near_misses
// (default promote), and the cone with its edges from the centre ray (coarse_test cone, edge_depth
// centre-ray); a config that an earlier log carries is read with what those sessions showed,
// mid-footprint-bilinear before 5, ignore before 6, ray and level before 10 (docs/log-schema.md,
// "Versions"). Relabelled
// an earlier schema (the chain then breaks, which replay also says), a session of today's defaults
// replays other FIPR images, and replay names the stimulus parameter it reads otherwise than the
// header recorded; one that showed that schema's defaults replays to its hashes, as every session
// of that schema does.
TEST(FiprSession, ALogOfAnEarlierSchemaReplaysWithThatSchemasDefault) {
  const auto frame_hash_differences = [](const ReplayOutcome& replayed) {
    int count = 0;
    for (const std::string& difference : replayed.differences)
      count += difference.find("frame hash") != std::string::npos;
    return count;
  };
  const auto relabelled = [](const std::string& log_path, int schema) {
    const fs::path path = fs::path(log_path).parent_path() / ("schema" + std::to_string(schema) + ".jsonl");
    std::ofstream(path, std::ios::binary) << relabelled_schema(read_file(log_path), schema);
    return path.string();
  };
  struct Case {
    const char* name;
    std::string config_lines;  // added to the test stimulus
    int claimed_schema;
    // What replay reads otherwise than the header recorded: it names a stimulus's first difference,
    // in key order.
    std::set<std::string> parameters_named;
  };
  // Schema 9's pyramid, named (ray, 3x3; its edges then read the centre ray's depth either way).
  const std::string ray = "coarse_test = \"ray\"\nmin_filter_size = 3\nedge_depth = \"level\"\n";
  const std::vector<Case> cases = {
      {"today's defaults as schema 9", "", 9, {"coarse_test"}},
      {"today's cone with schema 9's edges as schema 9",
       "min_filter_size = 3\nedge_depth = \"level\"\n",
       9,
       {"coarse_test"}},
      {"schema 9's cone as schema 9", "coarse_test = \"cone\"\nmin_filter_size = 3\nedge_depth = \"level\"\n", 9, {}},
      {"today's defaults but the pyramid as schema 4", ray, 4, {"near_misses"}},
      {"today's reconstruction as schema 4", ray + "near_misses = \"ignore\"\n", 4, {"periphery_reconstruction"}},
      {"today's defaults but the pyramid as schema 5", ray, 5, {"near_misses"}},
      {"schema 4's defaults",
       ray + "periphery_reconstruction = \"mid-footprint-bilinear\"\nnear_misses = \"ignore\"\n",
       4,
       {}},
      {"schema 5's defaults", ray + "near_misses = \"ignore\"\n", 5, {}},
      {"schema 9's defaults", ray, 9, {}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    std::string text = kFiprStudy;
    text.replace(text.find("mask_seed = 11\n"), 15, "mask_seed = 11\n" + c.config_lines);
    const fs::path results = fresh_folder("fipr-schema-" + std::to_string(&c - cases.data()));
    const SessionOutcome outcome = run_session(fipr_config(text), simulated_on_trace(results, still_trace(results)));
    ASSERT_TRUE(outcome.finished);
    EXPECT_EQ(replay(outcome.log_path).difference_count, 0);
    const ReplayOutcome earlier = replay(relabelled(outcome.log_path, c.claimed_schema));
    EXPECT_GT(earlier.difference_count, 0) << "the chain no longer holds";
    // Replay also compares the stimuli it makes of config_toml with those the header recorded.
    std::set<std::string> named;
    for (const std::string& difference : earlier.differences) {
      if (difference.find("header: stimulus") != 0) continue;
      for (const char* parameter : {"coarse_test", "edge_depth", "periphery_reconstruction", "near_misses"}) {
        if (difference.find("parameters." + std::string(parameter) + ": none by this build's reading") !=
            std::string::npos)
          named.insert(parameter);
      }
    }
    EXPECT_EQ(named, c.parameters_named) << (earlier.differences.empty() ? "" : earlier.differences.front());
    if (c.parameters_named.empty()) {
      EXPECT_EQ(frame_hash_differences(earlier), 0) << "the schema's defaults are what this session showed";
    } else {
      EXPECT_GT(frame_hash_differences(earlier), 0) << "the schema's defaults are not today's";
    }
  }
  // A header that lacks a parameter (as older headers lack one added since, at its default) is not a
  // difference of the stimuli; the frames then decide.
  const fs::path results = fresh_folder("fipr-schema-lacking");
  const SessionOutcome outcome = run_session(fipr_config(), simulated_on_trace(results, still_trace(results)));
  ASSERT_TRUE(outcome.finished);
  std::string lacking_text = read_file(outcome.log_path);
  const std::string recorded = "\"periphery_reconstruction\":\"bilinear\",";
  ASSERT_NE(lacking_text.find(recorded), std::string::npos) << "the header records today's default";
  for (size_t at; (at = lacking_text.find(recorded)) != std::string::npos;) lacking_text.erase(at, recorded.size());
  const fs::path lacking = results / "lacking.jsonl";
  std::ofstream(lacking, std::ios::binary) << lacking_text;
  const ReplayOutcome replayed = replay(lacking.string());
  for (const std::string& difference : replayed.differences)
    EXPECT_EQ(difference.find("header: stimulus"), std::string::npos) << difference;
  EXPECT_EQ(frame_hash_differences(replayed), 0);
}

TEST(FiprSession, EveryPresentationStartsAfreshSoTheSameGazeGivesTheSameImages) {
  const fs::path results = fresh_folder("fipr-still");
  const SessionOutcome outcome = run_session(fipr_config(), simulated_on_trace(results, still_trace(results)));
  ASSERT_TRUE(outcome.finished);
  // Each FIPR stimulus is shown twice (2 repeats), other stimuli in between: the two presentations
  // of a stimulus are image for image the same, though the periphery refresh keeps pixels of the
  // previous image within one.
  std::map<int, std::vector<std::vector<std::string>>> hashes_by_stimulus;
  for (const StimulusEvent& shown : fipr_presentations(outcome.log_path))
    hashes_by_stimulus[shown.stimulus].push_back(shown.hash);
  ASSERT_EQ(hashes_by_stimulus.size(), 2u);
  for (const auto& [stimulus, presentations] : hashes_by_stimulus) {
    ASSERT_EQ(presentations.size(), 2u) << "stimulus " << stimulus;
    EXPECT_EQ(presentations[0], presentations[1]) << "stimulus " << stimulus;
  }
  EXPECT_NE(hashes_by_stimulus.begin()->second.front(), hashes_by_stimulus.rbegin()->second.front())
      << "a 2.5 and a 10 degree fovea give other images";
  EXPECT_EQ(replay(outcome.log_path).difference_count, 0);
}

TEST(FiprSession, AResumedSessionReplays) {
  const fs::path results = fresh_folder("fipr-resume");
  const StudyConfig config = fipr_config();
  const fs::path trace = moving_trace(results, 60.0);
  const SessionOutcome whole = run_session(config, simulated_on_trace(results / "whole", trace));
  const std::string text = read_file(whole.log_path);
  // Cut the log inside the third trial's events (after its trial_start), then resume.
  size_t cut = text.find("\"event\":\"trial_start\"");
  for (int i = 0; i < 2 && cut != std::string::npos; ++i) cut = text.find("\"event\":\"trial_start\"", cut + 1);
  ASSERT_NE(cut, std::string::npos);
  cut = text.find('\n', cut) + 1;
  const std::string log_path = session_log_path((results / "cut").string(), config.name, "P1");
  fs::create_directories(fs::path(log_path).parent_path());
  std::ofstream(log_path, std::ios::binary) << text.substr(0, cut);
  const SessionOutcome resumed = run_session(config, simulated_on_trace(results / "cut", trace));
  EXPECT_TRUE(resumed.resumed);
  EXPECT_TRUE(resumed.finished);
  const ReplayOutcome replayed = replay(resumed.log_path);
  EXPECT_EQ(replayed.difference_count, 0) << (replayed.differences.empty() ? "" : replayed.differences.front());
  EXPECT_EQ(replayed.trials, 4);
}

// --- the library ------------------------------------------------------------------------------------

StimulusSpec fipr_spec(const StudyPlan& plan, double fovea_deg) {
  for (const PlannedStimulus& stimulus : plan.stimuli)
    if (stimulus.spec.method() == RenderMethod::foveated_pyramid && stimulus.level == fovea_deg) return stimulus.spec;
  throw std::logic_error("no FIPR stimulus");
}

class FiprLibrary : public VulkanTest {};

TEST_F(FiprLibrary, ImagesOfAPresentationFollowEachOtherAndIndexZeroRestarts) {
  const StudyPlan plan = make_study_plan(fipr_config(), "P1");
  StimulusSpec spec = fipr_spec(plan, 2.5);
  std::get<FoveatedPyramidParameters>(spec.parameters).periphery_refresh = 4;
  const StimulusSpec other = fipr_spec(plan, 10);
  StimulusLibrary library(context());
  const auto present = [&](const StimulusSpec& shown, double gaze_shift_px) {
    std::vector<std::string> hashes;
    for (int i = 0; i < 6; ++i) {
      StimulusImage image;
      image.frame = i / 3;
      image.image_index = i;
      image.gaze.x_px = 10.0 + 8.0 * i + gaze_shift_px;
      image.gaze.y_px = 40.0 - 5.0 * i;
      hashes.push_back(library.render(shown, image).hash);
    }
    return hashes;
  };
  const std::vector<std::string> first = present(spec, 0.0);
  // Other work on the same scene between two presentations: a GT frame, another FIPR stimulus,
  // the same stimulus with another gaze.
  StimulusSpec gt = plan.stimuli.at(0).spec;
  ASSERT_EQ(gt.method(), RenderMethod::ground_truth);
  library.render(gt, StimulusImage{});
  present(other, 0.0);
  const std::vector<std::string> moved = present(spec, 13.0);
  EXPECT_NE(moved, first);
  EXPECT_EQ(present(spec, 0.0), first);

  // The history matters: image 1 with the same gaze, after another image 0, is another image
  // (pixels not due keep image 0's colour, traced in full near image 0's gaze; in flat regions the
  // full and the mid-level colour agree, so a few places are tried).
  std::set<std::string> after_other_image0;
  for (const auto& [x, y] : {std::pair{32.0, 44.0}, {56.0, 40.0}, {40.0, 24.0}, {8.0, 20.0}}) {
    StimulusImage image0, image1;
    image0.gaze.x_px = x;
    image0.gaze.y_px = y;
    image1.image_index = 1;
    image1.gaze.x_px = 18.0;
    image1.gaze.y_px = 35.0;
    library.render(spec, image0);
    after_other_image0.insert(library.render(spec, image1).hash);
  }
  after_other_image0.erase(first[1]);
  EXPECT_FALSE(after_other_image0.empty());

  // Image k > 0 must directly follow image k - 1 of the same stimulus.
  StimulusImage second;
  second.image_index = 1;
  EXPECT_THROW(library.render(spec, second), std::logic_error);  // after image 5
  library.render(gt, StimulusImage{});
  EXPECT_THROW(library.render(spec, second), std::logic_error);  // after a GT frame
  library.render(other, StimulusImage{});
  EXPECT_THROW(library.render(spec, second), std::logic_error);  // after another stimulus's image
  library.render(spec, StimulusImage{});
  EXPECT_NO_THROW(library.render(spec, second));

  // frame() renders gaze-dependent stimuli live, the same way, and leaves the image on the device:
  // its hash comes when asked for (after the present), and a later render makes it stale.
  library.prepare({{0, gt}, {1, spec}});
  StimulusImage image;
  image.gaze.x_px = 10.0;
  image.gaze.y_px = 40.0;
  const PreparedFrame& live = library.frame(1, spec, image);
  EXPECT_TRUE(live.on_device);
  EXPECT_TRUE(live.hash.empty());
  EXPECT_EQ(library.hash(live), first.front());
  EXPECT_EQ(library.hash(live), first.front());  // asked again: the same
  const PreparedFrame& prepared = library.frame(0, gt, StimulusImage{});
  EXPECT_FALSE(prepared.on_device);
  EXPECT_EQ(library.hash(prepared), prepared.hash);
  const PreparedFrame copy = library.frame(1, spec, image);  // a copy, not the library's own
  EXPECT_THROW(library.hash(copy), std::logic_error);
}

}  // namespace
}  // namespace fovlab
