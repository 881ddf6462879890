// A study config with [display] kind = "openxr" at the command line: validate prints each eye's
// geometry and needs each eye's size; run refuses in one line (exit 2) what the runtime lacks and
// what headset sessions cannot do yet, before a results folder exists, and on a runtime with
// everything runs the study in the headset, both eyes logged and replayed. The runtime is the test runtime (tests/xr_runtime) in a child process (the loader
// of OpenXR 1.0.20 keeps one instance a process and caches what it listed), configured by its
// environment switches, with the OpenXR core validation layer on (its file must stay empty).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image_io.h"
#include "core/number_text.h"
#include "tests/app/cli_test_support.h"
#include "tests/app/headset_study_support.h"
#include "tests/display/openxr/openxr_test_support.h"
#include "tests/support/fovlab_child.h"

namespace fovlab {
namespace {

using cli_test::CommandResult;
using test::headset_study;
using test::HeadsetStudy;
using test::kEyesAtDistance;

// The refusal is one line on stderr; the validation layer's own line at load ("Core Validation
// output type: text, first time = true", on stderr, once an instance is made) is no message of fovlab's.
void expect_refusal(CommandResult result, const std::string& must_contain) {
  const std::string layer_line = "Core Validation output type: ";
  for (size_t at; (at = result.err.find(layer_line)) != std::string::npos;)
    result.err.erase(at, result.err.find('\n', at) + 1 - at);
  cli_test::expect_one_line_error(result, must_contain);
}

TEST_F(HeadsetStudy, ValidatePrintsEachEyesGeometry) {
  const CommandResult result =
      cli_test::run("validate " + write("a.toml", headset_study()).string() + " --no-render-timing");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("display openxr: 64x72 px an eye at 90 Hz, head-locked, gaze to each eye through the "
                            "rendered depth, IPD 63 mm\n"),
            std::string::npos)
      << result.out;
  // tan 54 + tan 49 = 2.5268 across 64 px: 0.4421 px/deg; tan 54 + tan 56 = 2.8590 down 72 px.
  EXPECT_NE(result.out.find("  left  eye [-54, 49, 54, -56] deg: 103.0 x 110.0 deg, 0.44 x 0.44 px/deg at the "
                            "view's centre (pixel 34.9, 34.7)\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("  right eye [-49, 54, 54, -56] deg: 103.0 x 110.0 deg, 0.44 x 0.44 px/deg at the "
                            "view's centre (pixel 29.1, 34.7)\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("gaze: gaze-contingent: a headset session takes the headset's eye gaze"), std::string::npos)
      << result.out;
}

// Each eye's size is the config's for every command, run included: "0, the runtime's recommended
// size" would give each participant stimuli of their own headset's size.
TEST_F(HeadsetStudy, EveryCommandRefusesTheRuntimesRecommendedSize) {
  const std::filesystem::path config = write("zero.toml", headset_study("eye_width_px = 0\neye_height_px = 0"));
  const std::string expected = config.string() +
                               ":7: display.eye_width_px: expected each eye's size in pixels, 8..16384, one size "
                               "for every participant of the study (`fovlab devices` prints the runtime's "
                               "recommended size), got 0";
  for (const std::string command : {"validate", "simulate", "prerender"}) {
    SCOPED_TRACE(command);
    expect_refusal(cli_test::run(command + " " + config.string(), "cd " + scratch_.path().string() + " &&"), expected);
  }
  expect_refusal(run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated --gaze synthetic:seed=3"),
                 expected);
  EXPECT_FALSE(std::filesystem::exists(results_));
}

TEST_F(HeadsetStudy, RunWithoutARuntimeRefusesInOneLine) {
  const CommandResult result =
      run_study(write("a.toml", headset_study()), "", (scratch_.path() / "missing.json").string());
  expect_refusal(result, "openxr: no OpenXR runtime (XR_ERROR_RUNTIME_UNAVAILABLE); ");
  EXPECT_NE(result.err.find("runs in a headset ([display] kind = \"openxr\")"), std::string::npos) << result.err;
  EXPECT_FALSE(std::filesystem::exists(results_));
}

TEST_F(HeadsetStudy, RunRefusesARuntimeWithoutVulkanOrAHeadset) {
  const std::filesystem::path config = write("a.toml", headset_study());
  expect_refusal(run_study(config, "FOVLAB_TEST_XR_VULKAN=absent"),
                 "openxr: the OpenXR runtime (fovlab test runtime 0.1.0) does not offer XR_KHR_vulkan_enable2; "
                 "fovlab renders through Vulkan");
  expect_refusal(run_study(config, "FOVLAB_TEST_XR_HEADSET=absent"),
                 "openxr: no headset (xrGetSystem: XR_ERROR_FORM_FACTOR_UNAVAILABLE) on the OpenXR runtime "
                 "fovlab test runtime 0.1.0");
  EXPECT_FALSE(std::filesystem::exists(results_));
}

// A gaze-contingent study needs the headset's eye gaze, unless a trace or synthetic source is named.
TEST_F(HeadsetStudy, RunRefusesAGazeContingentStudyWithoutEyeGazeUnlessTheGazeIsNamed) {
  const CommandResult devices =
      cli_test::run("devices", child_environment(FOVLAB_TEST_XR_RUNTIME_JSON) + " FOVLAB_TEST_XR_EYE_GAZE=absent");
  ASSERT_EQ(devices.exit_code, 0) << devices.err;
  EXPECT_NE(devices.out.find("XR_KHR_vulkan_enable2: yes, XR_EXT_eye_gaze_interaction: no"), std::string::npos)
      << devices.out;
  const std::filesystem::path config = write("a.toml", headset_study());
  const CommandResult refused = run_study(config, "FOVLAB_TEST_XR_EYE_GAZE=absent");
  expect_refusal(refused, config.string() +
                              ": a gaze-contingent study (fipr follows the gaze) needs the "
                              "headset's eye gaze, and the OpenXR runtime fovlab test runtime "
                              "0.1.0 does not offer XR_EXT_eye_gaze_interaction");
  // Named in the config or on the command line: past this refusal, to the next one (the right eye's
  // angles, made to differ from the runtime's so that the session stops there).
  const auto other_angles = [](std::string text) {
    return text.replace(text.find("[-49, 54, 54, -56]"), 18, "[-49, 54, 54, -55]");
  };
  const std::filesystem::path synthetic = write(
      "synthetic.toml",
      other_angles(headset_study("eye_width_px = 64\neye_height_px = 72", "\n[gaze]\nrequire = \"synthetic\"\n")));
  const std::filesystem::path angles = write("angles.toml", other_angles(headset_study()));
  const std::string next_refusal = "display.right_eye_fov_deg: the headset's runtime";
  expect_refusal(run_study(synthetic, "FOVLAB_TEST_XR_EYE_GAZE=absent"), next_refusal);
  expect_refusal(
      run_study(angles, "FOVLAB_TEST_XR_EYE_GAZE=absent", FOVLAB_TEST_XR_RUNTIME_JSON, " --gaze synthetic:seed=3"),
      next_refusal);
  EXPECT_FALSE(std::filesystem::exists(results_));
}

TEST_F(HeadsetStudy, RunRefusesAnEyeOverTheRuntimesMaximumNamingTheKey) {
  const std::filesystem::path config = write("large.toml", headset_study("eye_width_px = 4000\neye_height_px = 1600"));
  expect_refusal(run_study(config), config.string() +
                                        ":7: display.eye_width_px: expected an eye image of at most the "
                                        "runtime's 2880x3200 (fovlab test runtime 0.1.0), got 4000x1600");
  EXPECT_FALSE(std::filesystem::exists(results_));
}

// What headset sessions cannot do yet is refused in one line before a results folder exists: the
// gaze resting on the rendered depth of volume stimuli (no surface), a field of view that is not the
// runtime's, the headset's eye gaze from a runtime without it.
TEST_F(HeadsetStudy, RunRefusesWhatHeadsetSessionsCannotDoYet) {
  const std::string synthetic = " --observer simulated --gaze synthetic:seed=3";
  std::string volumes = headset_study();
  volumes.replace(volumes.find("method = \"gt\""), 13, "method = \"volume\"");
  volumes.replace(volumes.find("method = \"fipr\""), 15, "method = \"fvolume\"");
  volumes.replace(volumes.find("fovea_radius_deg"), 16, "density_sigma_deg");
  volumes.replace(volumes.find("values = [5, 10]"), 16, "values = [0.5, 3.0]");
  volumes.replace(volumes.find("scene = \"primitives\""), 20, "scene = \"shepp-logan\"");
  const std::filesystem::path depth = write("volume_depth.toml", volumes);
  expect_refusal(run_study(depth, "", FOVLAB_TEST_XR_RUNTIME_JSON, synthetic),
                 depth.string() +
                     ": display.gaze_fixation: \"rendered-depth\" rests the gaze on the surface the "
                     "sphere tracer finds, and method ");
  const std::filesystem::path no_tracker = write("no_tracker.toml", headset_study(kEyesAtDistance));
  expect_refusal(run_study(no_tracker, "FOVLAB_TEST_XR_EYE_GAZE=absent", FOVLAB_TEST_XR_RUNTIME_JSON,
                           " --observer simulated --gaze openxr"),
                 "does not offer XR_EXT_eye_gaze_interaction");
  std::string other_angles = headset_study(kEyesAtDistance);
  other_angles.replace(other_angles.find("[-49, 54, 54, -56]"), 18, "[-49, 54, 54, -55]");
  const std::filesystem::path angles = write("angles.toml", other_angles);
  expect_refusal(run_study(angles, "", FOVLAB_TEST_XR_RUNTIME_JSON, synthetic),
                 angles.string() +
                     ": display.right_eye_fov_deg: the headset's runtime (fovlab test runtime 0.1.0) "
                     "gives this eye [-49, 54, 54, -56] deg, the config [-49, 54, 54, -55] deg");
  for (const std::string flag : {"--headless", "--device 0", "--present-device 0"})
    expect_refusal(run_study(depth, "", FOVLAB_TEST_XR_RUNTIME_JSON, synthetic + " " + flag),
                   flag.substr(0, flag.find(' ')) + (flag == "--headless" ? ": " : flag.substr(flag.find(' ')) + ": ") +
                       depth.string() + " runs in a headset");
  EXPECT_FALSE(std::filesystem::exists(results_ / "headset_cli" / "P01" / "events.jsonl"));
}

// A simulated observer runs a FIPR study in the test runtime's headset, each eye rendered from its
// own view with its own gaze; the log holds both eyes, replays to their hashes, and analyzes.
// The centroid of a screenshot's lit pixels (the validation target's grey disk), in pixels.
std::array<double, 2> lit_centroid(const std::filesystem::path& png) {
  const Image image = read_image(png);
  double x_sum = 0.0, y_sum = 0.0, count = 0.0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      if (image.pixels[(static_cast<size_t>(y) * image.width + x) * image.channels] > 0.4f) {
        x_sum += x;
        y_sum += y;
        count += 1.0;
      }
  if (count == 0.0) return {std::nan(""), std::nan("")};
  return {x_sum / count, y_sum / count};
}

// The eye-tracker validation in the headset shows each eye the one target. With rendered-depth
// (nothing is drawn behind a target) it is at optical infinity: one direction, which each eye sees
// where that direction's tangent falls between its own angles. The test runtime's eyes are
// mirrored ([-54, 49] and [-49, 54] degrees across, both [54, -56] up and down), so the right eye's
// disk is left of the left's, on the same row; worked out here from the angles alone.
TEST_F(HeadsetStudy, TheTrackerValidationShowsEachEyeTheOneTarget) {
  const std::filesystem::path config =
      write("v.toml", headset_study("eye_width_px = 64\neye_height_px = 72",
                                    "\n[validation]\ntargets = 5\ntarget_radius_deg = 2\n"));
  const std::filesystem::path shots = scratch_.path() / "shots";
  const CommandResult ran = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON,
                                      " --observer simulated --gaze synthetic:seed=3 --screenshots " + shots.string());
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_NE(ran.err.find("eye-tracker validation (start, attempt 1 of 3)"), std::string::npos) << ran.err;
  const std::array<double, 2> left = lit_centroid(shots / "validation_target.png");
  const std::array<double, 2> right = lit_centroid(shots / "validation_target_right_eye.png");
  ASSERT_TRUE(std::isfinite(left[0]) && std::isfinite(right[0]));
  const auto tan_deg = [](double deg) { return std::tan(deg * std::numbers::pi / 180.0); };
  const double tangent = tan_deg(-54.0) + (left[0] + 0.5) / 64.0 * (tan_deg(49.0) - tan_deg(-54.0));
  const double expected_right_x = (tangent - tan_deg(-49.0)) / (tan_deg(54.0) - tan_deg(-49.0)) * 64.0 - 0.5;
  EXPECT_NEAR(right[0], expected_right_x, 0.6);
  EXPECT_NEAR(right[1], left[1], 0.6);
  EXPECT_GT(left[0] - right[0], 3.0) << "the right eye's target is not the left eye's pixel again";
}

TEST_F(HeadsetStudy, ASimulatedObserverRunsAStudyInTheHeadsetThatReplaysBothEyes) {
  const std::filesystem::path config = write("a.toml", headset_study(kEyesAtDistance));
  const CommandResult ran =
      run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated --gaze synthetic:seed=3");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  // Not the runtime's recommended size: said once, as the session starts (the compositor resamples).
  const std::string resampled =
      "fovlab: each eye renders at 64x72 px (the config's); the runtime fovlab test runtime "
      "0.1.0 recommends 1440x1600 px, so its compositor resamples each eye's image\n";
  EXPECT_NE(ran.err.find(resampled), std::string::npos) << ran.err;
  EXPECT_EQ(ran.err.find(resampled), ran.err.rfind(resampled)) << ran.err;
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  std::ifstream lines(log);
  std::string line;
  ASSERT_TRUE(std::getline(lines, line));
  const nlohmann::json header = nlohmann::json::parse(line);
  EXPECT_EQ(header.value("presenter", ""), "openxr");
  ASSERT_TRUE(header.contains("headset")) << line;
  const nlohmann::json& headset = header["headset"];
  EXPECT_EQ(headset.value("runtime", ""), "fovlab test runtime 0.1.0");
  EXPECT_EQ(headset["eyes"].size(), 2u);
  EXPECT_NEAR(headset["eyes"][1]["position_m"][0].get<double>() - headset["eyes"][0]["position_m"][0].get<double>(),
              0.063, 1e-6);
  int stimuli = 0, eyes_differ = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    ++stimuli;
    ASSERT_TRUE(event.contains("right_eye_hash")) << line;
    ASSERT_EQ(event["right_eye_hash"].size(), event["hash"].size());
    ASSERT_EQ(event["right_eye_gaze"].size(), event["gaze"].size());
    EXPECT_EQ(event.value("present_clock", ""), "openxr_predicted_display");
    if (event["right_eye_hash"] != event["hash"]) ++eyes_differ;
    // The same fixation point is seen from two places: the right eye's pixel lies left of the left's
    // (a point at 1.5 m in front of the head).
    EXPECT_LT(event["right_eye_gaze"][0][0].get<double>(), event["gaze"][0][0].get<double>() + 10.0) << line;
  }
  EXPECT_EQ(stimuli, 4);  // 2 trials of 2 stimuli
  EXPECT_EQ(eyes_differ, stimuli) << "each eye sees the scene from its own place";

  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
  EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;
  const CommandResult analyzed = cli_test::run("analyze " + (results_ / "headset_cli").string() + " --out " +
                                               (scratch_.path() / "report").string());
  EXPECT_EQ(analyzed.exit_code, 0) << analyzed.err;
}

// Without --gaze, a headset session takes the headset's eye gaze: the test runtime's ray, 10 degrees
// right and 5 up of straight ahead, rests on the plane 1.5 m in front of the head, and each eye's
// logged pixel is where that point appears to it (computed here from the logged views).
TEST_F(HeadsetStudy, TheHeadsetsEyeGazeGivesEachEyeThePixelOfTheFixationPoint) {
  const std::filesystem::path config = write("a.toml", headset_study(kEyesAtDistance));
  const CommandResult ran =
      run_study(config, "FOVLAB_TEST_XR_GAZE=10,5", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  std::ifstream lines(results_ / "headset_cli" / "P01" / "events.jsonl");
  std::string line;
  ASSERT_TRUE(std::getline(lines, line));
  const nlohmann::json header = nlohmann::json::parse(line);
  EXPECT_EQ(header.value("gaze", ""), "openxr");
  EXPECT_EQ(header["gaze_source"].value("kind", ""), "tracker");
  const double pi = std::acos(-1.0);
  const std::array<double, 3> point{1.5 * std::tan(10.0 * pi / 180.0),
                                    1.5 * std::tan(5.0 * pi / 180.0) / std::cos(10.0 * pi / 180.0), -1.5};
  std::array<std::array<double, 2>, 2> expected{};
  for (size_t eye = 0; eye < 2; ++eye) {
    // Each eye looks straight ahead (the test runtime's orientation is the head's).
    const nlohmann::json& view = header["headset"]["eyes"][eye];
    const double tan_x = (point[0] - view["position_m"][0].get<double>()) / -point[2];
    const double tan_y = (point[1] - view["position_m"][1].get<double>()) / -point[2];
    const std::array<double, 4> fov = view["fov_rad"].get<std::array<double, 4>>();
    expected[eye] = {64 * (tan_x - std::tan(fov[0])) / (std::tan(fov[1]) - std::tan(fov[0])),
                     72 * (std::tan(fov[2]) - tan_y) / (std::tan(fov[2]) - std::tan(fov[3]))};
  }
  int stimuli = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    ++stimuli;
    EXPECT_FALSE(event.contains("invalid_gaze") && !event["invalid_gaze"].empty()) << line;
    for (size_t i = 0; i < event["gaze"].size(); ++i) {
      EXPECT_NEAR(event["gaze"][i][0].get<double>(), expected[0][0], 0.006) << line;
      EXPECT_NEAR(event["gaze"][i][1].get<double>(), expected[0][1], 0.006) << line;
      EXPECT_NEAR(event["right_eye_gaze"][i][0].get<double>(), expected[1][0], 0.006) << line;
      EXPECT_NEAR(event["right_eye_gaze"][i][1].get<double>(), expected[1][1], 0.006) << line;
    }
  }
  EXPECT_EQ(stimuli, 4);
  EXPECT_GT(expected[0][0] - expected[1][0], 1.0) << "the near point appears further left to the right eye";
}

// Each eye's gaze quality in the report (report.html's Headset section; thresholds.json's
// participants[].headset): the test runtime's gaze turns 52 degrees left for the frames 1-300,
// inside the left eye's left edge (54 degrees) but past the right eye's (49; the right eye sees the
// fixation point a little further left still), and is lost (not tracked) for the frames 301-420. A
// refresh's gaze is located at the predicted display time of the frame before the one that shows
// it, so the refreshes off the right eye's image and without a gaze are counted here from the
// logged present times alone, and the shares must be exactly those (right_eye_invalid_gaze, schema 13).
TEST_F(HeadsetStudy, TheReportGivesEachEyesShareOfGazeOffItsImageAndNotTracked) {
  const std::filesystem::path config = write("a.toml", headset_study(kEyesAtDistance));
  const CommandResult ran = run_study(config, "FOVLAB_TEST_XR_GAZE_AWAY=1,300,-52,0 FOVLAB_TEST_XR_GAZE_LOST=301,420",
                                      FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  std::ifstream lines(results_ / "headset_cli" / "P01" / "events.jsonl");
  int refreshes = 0, off_right_image = 0, not_tracked = 0;
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    for (const nlohmann::json& present_s : event["present_s"]) {
      const int64_t located_frame = std::llround(present_s.get<double>() * 90.0);  // shown at that + 1
      ++refreshes;
      if (located_frame >= 1 && located_frame <= 300) ++off_right_image;
      if (located_frame >= 301 && located_frame <= 420) ++not_tracked;
    }
  }
  ASSERT_GT(off_right_image, 0) << "no stimulus in frames 1-300";
  ASSERT_GT(not_tracked, 0) << "no stimulus in frames 301-420";
  ASSERT_LT(off_right_image + not_tracked, refreshes) << "every refresh in the scripted frames";

  const std::filesystem::path report = scratch_.path() / "report";
  const CommandResult analyzed =
      cli_test::run("analyze " + (results_ / "headset_cli").string() + " --out " + report.string());
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.err;
  std::ifstream thresholds_file(report / "thresholds.json");
  const nlohmann::json headset = nlohmann::json::parse(thresholds_file)["participants"][0]["headset"];
  EXPECT_EQ(headset.value("gaze_refreshes", -1), refreshes) << headset;
  const nlohmann::json& left = headset["eyes"][0];
  const nlohmann::json& right = headset["eyes"][1];
  EXPECT_DOUBLE_EQ(left.value("gaze_off_image_share", -1.0), 0.0) << headset;
  EXPECT_DOUBLE_EQ(left.value("gaze_invalid_share", -1.0), double(not_tracked) / refreshes) << headset;
  EXPECT_DOUBLE_EQ(right.value("gaze_invalid_share", -1.0), double(not_tracked) / refreshes) << headset;
  EXPECT_DOUBLE_EQ(right.value("gaze_off_image_share", -1.0), double(off_right_image) / refreshes) << headset;

  std::ifstream html_file(report / "report.html");
  const std::string html((std::istreambuf_iterator<char>(html_file)), std::istreambuf_iterator<char>());
  const auto share = [&](int count) {
    std::ostringstream text;
    text << format_number(100.0 * (static_cast<double>(count) / refreshes), 3) << "% (" << count << " of " << refreshes
         << ")";
    return text.str();
  };
  // The left eye's row, then the right eye's: invalid, off the image, either.
  EXPECT_NE(html.find("<td>left</td><td>" + share(not_tracked) + "</td><td>" + share(0) + "</td><td>" +
                      share(not_tracked) + "</td>"),
            std::string::npos)
      << html.substr(html.find("id=\"headset\""), 6000);
  EXPECT_NE(html.find("<td>right</td><td>" + share(not_tracked) + "</td><td>" + share(off_right_image) + "</td><td>" +
                      share(not_tracked + off_right_image) + "</td>"),
            std::string::npos);
}

// With gaze_fixation = "rendered-depth" (the default), the headset's eye gaze rests where its ray
// meets the scene shown: the test runtime's ray, 10 degrees right and 5 up from the head's origin,
// meets the wall of tests/fixtures/scenes/gaze_wall.glsl (the plane z = -1 of the head, the camera
// still) at the analytic point, and each eye's logged pixel is where that point appears to it.
TEST_F(HeadsetStudy, TheHeadsetsEyeGazeRestsOnTheRenderedDepth) {
  const std::string wall = std::string(FOVLAB_SOURCE_DIR) + "/tests/fixtures/scenes/gaze_wall.glsl";
  std::string text = headset_study();
  text.replace(text.find("scene = \"primitives\""), 20, "scene = \"" + wall + "\"");
  const std::filesystem::path config = write("depth.toml", text);
  const CommandResult ran =
      run_study(config, "FOVLAB_TEST_XR_GAZE=10,5", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  std::ifstream lines(log);
  std::string line;
  ASSERT_TRUE(std::getline(lines, line));
  const nlohmann::json header = nlohmann::json::parse(line);
  EXPECT_EQ(header["headset"]["gaze_fixation"], nlohmann::json({{"kind", "rendered-depth"}})) << line;
  const double pi = std::acos(-1.0);
  const double deg = pi / 180.0;
  // The ray's direction scaled to reach z = -1: the analytic hit point.
  const std::array<double, 3> point{std::tan(10.0 * deg), std::tan(5.0 * deg) / std::cos(10.0 * deg), -1.0};
  const double hit_m = std::hypot(point[0], point[1], point[2]);
  // The tolerance: the march stops short of the wall by at most hit band x t / cos(incidence) along
  // the ray (SphereTracer::hit_distance), the band being GT's hit_threshold (0.25) x the left eye's
  // pixel angle ((tan 54 + tan 56) / 72 px); so the point is at most band x t nearer in depth. An
  // eye e metres off the ray's origin sees it moved by e x that / depth^2 in tan-angle (plus the
  // second order), times its pixels per tan-angle; the log rounds to 0.01 px.
  const double band_rad = 0.25 * (std::tan(54.0 * deg) + std::tan(56.0 * deg)) / 72.0;
  const double depth_short_m = band_rad * hit_m;
  std::array<std::array<double, 2>, 2> expected{}, tolerance{};
  for (size_t eye = 0; eye < 2; ++eye) {
    // Each eye looks straight ahead (the test runtime's orientation is the head's).
    const nlohmann::json& view = header["headset"]["eyes"][eye];
    const std::array<double, 3> position = view["position_m"].get<std::array<double, 3>>();
    const double tan_x = (point[0] - position[0]) / (position[2] - point[2]);
    const double tan_y = (point[1] - position[1]) / (position[2] - point[2]);
    const std::array<double, 4> fov = view["fov_rad"].get<std::array<double, 4>>();
    const double px_per_tan_x = 64 / (std::tan(fov[1]) - std::tan(fov[0]));
    const double px_per_tan_y = 72 / (std::tan(fov[2]) - std::tan(fov[3]));
    expected[eye] = {px_per_tan_x * (tan_x - std::tan(fov[0])), px_per_tan_y * (std::tan(fov[2]) - tan_y)};
    const double shift_per_offset = depth_short_m / (1.0 - depth_short_m);  // 1/(1 - d) - 1 at depth 1
    tolerance[eye] = {px_per_tan_x * std::abs(point[0] - position[0]) * shift_per_offset + 0.005 + 1e-9,
                      px_per_tan_y * std::abs(point[1] - position[1]) * shift_per_offset + 0.005 + 1e-9};
  }
  int stimuli = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    ++stimuli;
    EXPECT_FALSE(event.contains("invalid_gaze") && !event["invalid_gaze"].empty()) << line;
    for (size_t i = 0; i < event["gaze"].size(); ++i) {
      EXPECT_NEAR(event["gaze"][i][0].get<double>(), expected[0][0], tolerance[0][0]) << line;
      EXPECT_NEAR(event["gaze"][i][1].get<double>(), expected[0][1], tolerance[0][1]) << line;
      EXPECT_NEAR(event["right_eye_gaze"][i][0].get<double>(), expected[1][0], tolerance[1][0]) << line;
      EXPECT_NEAR(event["right_eye_gaze"][i][1].get<double>(), expected[1][1], tolerance[1][1]) << line;
    }
  }
  EXPECT_EQ(stimuli, 4);
  // The wall's 1 m from the gaze at optical infinity: the eyes' pixels would differ by the IPD over
  // 1 m, about 1.6 px, far beyond the tolerance.
  EXPECT_LT(tolerance[1][0], 0.05);
  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
  EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;
}

// A source that gives the left eye's pixels (synthetic) with rendered-depth: the right eye's logged
// pixel is where it sees the point at which the left eye's ray through the logged left pixel meets
// gaze_wall.glsl's ball or wall, found here analytically. The march stops short of the surface by
// at most band x t / cos(incidence) along the ray (SphereTracer::hit_distance): the right eye's pixel
// lies between those of the analytic point and of the point that much nearer, plus the log's
// rounding. Grazing samples (cos under 0.2) are only checked to be valid.
TEST_F(HeadsetStudy, APixelSourcesGazeRestsOnTheRenderedDepthAlongTheLeftEyesRay) {
  const std::string wall = std::string(FOVLAB_SOURCE_DIR) + "/tests/fixtures/scenes/gaze_wall.glsl";
  std::string text = headset_study();
  text.replace(text.find("scene = \"primitives\""), 20, "scene = \"" + wall + "\"");
  const std::filesystem::path config = write("depth.toml", text);
  const CommandResult ran =
      run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated --gaze synthetic:seed=3");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  std::ifstream lines(results_ / "headset_cli" / "P01" / "events.jsonl");
  std::string line;
  ASSERT_TRUE(std::getline(lines, line));
  const nlohmann::json header = nlohmann::json::parse(line);
  using Vec3 = std::array<double, 3>;
  std::array<Vec3, 2> position{};
  std::array<std::array<double, 4>, 2> tan{};  // left, right, up, down
  for (size_t eye = 0; eye < 2; ++eye) {
    position[eye] = header["headset"]["eyes"][eye]["position_m"].get<Vec3>();
    const std::array<double, 4> fov = header["headset"]["eyes"][eye]["fov_rad"].get<std::array<double, 4>>();
    for (size_t i = 0; i < 4; ++i) tan[eye][i] = std::tan(fov[i]);
  }
  // Each eye looks straight ahead (the test runtime's orientation is the head's).
  const auto pixel_in = [&](size_t eye, const Vec3& p) {
    const double depth = position[eye][2] - p[2];
    return std::array<double, 2>{64 * ((p[0] - position[eye][0]) / depth - tan[eye][0]) / (tan[eye][1] - tan[eye][0]),
                                 72 * (tan[eye][2] - (p[1] - position[eye][1]) / depth) / (tan[eye][2] - tan[eye][3])};
  };
  const double band_rad = 0.25 * (tan[0][2] - tan[0][3]) / 72.0;
  int checked = 0, samples = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    ASSERT_FALSE(event.contains("invalid_gaze") && !event["invalid_gaze"].empty()) << line;
    for (size_t i = 0; i < event["gaze"].size(); ++i, ++samples) {
      const double x = event["gaze"][i][0].get<double>(), y = event["gaze"][i][1].get<double>();
      const Vec3 o = position[0];
      Vec3 d{tan[0][0] + (tan[0][1] - tan[0][0]) * x / 64, tan[0][2] + (tan[0][3] - tan[0][2]) * y / 72, -1.0};
      const double n = std::hypot(d[0], d[1], d[2]);
      for (double& v : d) v /= n;
      // The ball (centre c, radius 0.2) if the ray meets it, else the wall z = -1.
      const Vec3 c{-0.5, 0.0, -0.7}, oc{o[0] - c[0], o[1] - c[1], o[2] - c[2]};
      const double b = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
      const double disc = b * b - (oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - 0.04);
      double t = (-1.0 - o[2]) / d[2], cos_incidence = -d[2];
      if (disc >= 0.0 && -b - std::sqrt(disc) > 0.0) {
        t = -b - std::sqrt(disc);
        const Vec3 normal{(oc[0] + t * d[0]) / 0.2, (oc[1] + t * d[1]) / 0.2, (oc[2] + t * d[2]) / 0.2};
        cos_incidence = -(normal[0] * d[0] + normal[1] * d[1] + normal[2] * d[2]);
      }
      if (cos_incidence < 0.2) continue;
      const double short_m = band_rad * t / cos_incidence;
      const auto far = pixel_in(1, {o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]});
      const auto near =
          pixel_in(1, {o[0] + (t - short_m) * d[0], o[1] + (t - short_m) * d[1], o[2] + (t - short_m) * d[2]});
      const double right_x = event["right_eye_gaze"][i][0].get<double>(),
                   right_y = event["right_eye_gaze"][i][1].get<double>();
      EXPECT_GE(right_x, std::min(far[0], near[0]) - 0.0051) << line;
      EXPECT_LE(right_x, std::max(far[0], near[0]) + 0.0051) << line;
      EXPECT_GE(right_y, std::min(far[1], near[1]) - 0.0051) << line;
      EXPECT_LE(right_y, std::max(far[1], near[1]) + 0.0051) << line;
      ++checked;
    }
  }
  EXPECT_GT(samples, 0);
  EXPECT_GT(checked, samples / 2) << "most samples meet the wall or the ball head-on enough";
}

// experiments/fipr_main_hmd.toml's gaze_fixation ("rendered-depth") is no longer refused: a copy at
// 64x72 an eye runs in the test runtime, with the headset's eye gaze, through its first trial (then
// it is stopped: the whole study is hours), both eyes' gaze logged on the built-in scenes.
TEST_F(HeadsetStudy, TheFiprMainHeadsetStudyRunsWithTheGazeOnTheRenderedDepth) {
  std::ifstream experiment(std::string(FOVLAB_SOURCE_DIR) + "/experiments/fipr_main_hmd.toml");
  std::string text = (std::stringstream() << experiment.rdbuf()).str();
  ASSERT_NE(text.find("gaze_fixation = \"rendered-depth\""), std::string::npos);
  text.replace(text.find("eye_width_px = 1440"), 19, "eye_width_px = 64");
  text.replace(text.find("eye_height_px = 1600"), 20, "eye_height_px = 72");
  const std::filesystem::path config = write("fipr_main_hmd.toml", text);
  const std::filesystem::path output = scratch_.path() / "first_trial.txt";
  const pid_t pid = test::start_fovlab(
      {"run", config.string(), "--participant", "P01", "--results", results_.string(), "--observer", "simulated"},
      "trial_end:1", output);
  ASSERT_TRUE(test::wait_until_stopped(pid)) << (std::stringstream() << std::ifstream(output).rdbuf()).str();
  kill(pid, SIGKILL);
  test::exit_code(pid);
  std::ifstream lines(results_ / "fipr_main_hmd" / "P01" / "events.jsonl");
  std::string line;
  ASSERT_TRUE(std::getline(lines, line)) << (std::stringstream() << std::ifstream(output).rdbuf()).str();
  const nlohmann::json header = nlohmann::json::parse(line);
  EXPECT_EQ(header["headset"]["gaze_fixation"], nlohmann::json({{"kind", "rendered-depth"}})) << line;
  EXPECT_EQ(header.value("gaze", ""), "openxr");
  int stimuli = 0;
  while (std::getline(lines, line)) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    ++stimuli;
    ASSERT_EQ(event["right_eye_gaze"].size(), event["gaze"].size()) << line;
    EXPECT_FALSE(event.contains("invalid_gaze") && !event["invalid_gaze"].empty()) << line;
  }
  EXPECT_EQ(stimuli, 2) << "the first trial's two sequences";
}

// A headset session killed (SIGKILL) after its first trial resumes after that trial, as a desktop
// one does, with the views it started with; the finished log replays both eyes to their hashes.
TEST_F(HeadsetStudy, AHeadsetSessionKilledAfterATrialResumesAndReplays) {
  const std::filesystem::path config = write("a.toml", headset_study(kEyesAtDistance));
  const std::filesystem::path output = scratch_.path() / "killed.txt";
  const pid_t pid = test::start_fovlab({"run", config.string(), "--participant", "P01", "--results", results_.string(),
                                        "--observer", "simulated", "--gaze", "synthetic:seed=3"},
                                       "trial_end:1", output);
  ASSERT_TRUE(test::wait_until_stopped(pid)) << (std::stringstream() << std::ifstream(output).rdbuf()).str();
  kill(pid, SIGKILL);
  test::exit_code(pid);
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  ASSERT_TRUE(std::filesystem::exists(log));

  const CommandResult resumed =
      run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, " --observer simulated --gaze synthetic:seed=3");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resumed, 2 of 2 trials complete"), std::string::npos) << resumed.out;
  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
  EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;
}

// A participant answers on the controller: the test runtime's Xbox controller presses A and B in
// turn every 30 frames, the presses reach the protocol as its pad_a ("same") and pad_b
// ("different") keys, and the session logs them as the answers, with their times.
TEST_F(HeadsetStudy, AParticipantAnswersOnTheController) {
  const std::filesystem::path config = write("a.toml", headset_study(kEyesAtDistance));
  std::string script;
  for (int frame = 30, n = 0; frame <= 6000; frame += 30, ++n)
    script +=
        std::to_string(frame) + (n % 2 == 0 ? " /user/gamepad/input/a/click\n" : " /user/gamepad/input/b/click\n");
  const std::filesystem::path presses = write("presses.txt", script);
  const CommandResult ran = run_study(config, "FOVLAB_TEST_XR_INPUT=" + presses.string() + " </dev/null",
                                      FOVLAB_TEST_XR_RUNTIME_JSON, " --gaze synthetic:seed=3");
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_NE(ran.out.find("new session, 2 of 2 trials complete"), std::string::npos) << ran.out;
  std::ifstream lines(results_ / "headset_cli" / "P01" / "events.jsonl");
  int responses = 0;
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") == "instructions") {
      EXPECT_GT(event.value("shown_s", 0.0), 0.0) << line;
    }
    if (event.value("event", "") != "response") continue;
    ++responses;
    const std::string key = event.value("key", "");
    EXPECT_TRUE(key == "pad_a" || key == "pad_b") << line;
    EXPECT_EQ(event.value("answer", ""), key == "pad_a" ? "same" : "different") << line;
    EXPECT_GT(event.value("rt_s", 0.0), 0.0) << line;
  }
  EXPECT_EQ(responses, 2);
}

// The emulated foveated path tracer in the headset: `fovlab prerender` makes each eye's frames (a
// cache folder an eye, none for the desktop's view), the session shows each eye its own, blended
// by its own gaze, and the log replays both eyes.
TEST_F(HeadsetStudy, AnFptStudyIsPreRenderedPerEyeAndRunsInTheHeadset) {
  const std::string config_text = R"([study]
name = "headset_fpt"
seed = 21

[display]
kind = "openxr"
eye_width_px = 32
eye_height_px = 36
refresh_hz = 90
left_eye_fov_deg = [-54, 49, 54, -56]
right_eye_fov_deg = [-49, 54, 54, -56]
gaze_fixation = "fixation-distance"
fixation_distance_mm = 4000

[stimulus]
duration_s = 0.0667
frames_per_second = 30
camera_start_s = 3.0

[stimulus.reference]
method = "pt"
samples_per_pixel = 2
max_bounces = 2

[stimulus.test]
method = "fpt"
samples_per_pixel = 2
max_bounces = 2

[levels]
parameter = "foveal_aperture_deg"
values = [5, 20]
higher_is_better = true

[protocol]
kind = "pair"
repeats = 1

[[block]]
scene = "courtyard"
)";
  const std::filesystem::path config = write("fpt.toml", config_text);
  const std::filesystem::path cache = scratch_.path() / "cache";
  const CommandResult prerendered = cli_test::run("prerender " + config.string() + " --cache " + cache.string());
  ASSERT_EQ(prerendered.exit_code, 0) << prerendered.out << prerendered.err;
  int folders = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cache)) {
    if (!entry.is_directory()) continue;
    ++folders;
    std::ifstream manifest(entry.path() / "cache.json");
    const nlohmann::json described = nlohmann::json::parse(manifest);
    EXPECT_NE(described.value("sequence", "").find(";eye=position:"), std::string::npos) << described.dump();
  }
  EXPECT_EQ(folders, 2) << "one sequence an eye";
  const auto frame_files = [&] {
    int count = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(cache))
      count += entry.path().extension() == ".exr" ? 1 : 0;
    return count;
  };
  const int prerendered_frames = frame_files();
  EXPECT_EQ(prerendered_frames, 4) << "2 frames an eye";

  const CommandResult ran = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON,
                                      " --observer simulated --gaze synthetic:seed=3 --cache " + cache.string());
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  EXPECT_EQ(frame_files(), prerendered_frames) << "the session found each eye's frames in the cache";
  const std::filesystem::path log = results_ / "headset_fpt" / "P01" / "events.jsonl";
  std::ifstream lines(log);
  int stimuli = 0, eyes_differ = 0;
  for (std::string line; std::getline(lines, line);) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") != "stimulus") continue;
    ++stimuli;
    ASSERT_TRUE(event.contains("right_eye_hash")) << line;
    if (event["right_eye_hash"] != event["hash"]) ++eyes_differ;
  }
  EXPECT_GT(stimuli, 0);
  EXPECT_EQ(eyes_differ, stimuli);
  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify --cache " + cache.string());
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
  EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;
}

// The headset losing the focus mid-session (the test runtime's VISIBLE at frame 400, as a headset
// taken off) pauses the study as a closed window does: session_paused with the reason, the log
// sealed; when the focus does not come back within --refocus-timeout (1 s here), the run exits, the
// next run resumes it to the end, and the log replays (openxr_session_life_test.cpp: the focus back).
TEST_F(HeadsetStudy, LosingTheFocusPausesTheSessionAndTheNextRunResumesIt) {
  const std::filesystem::path config = write("a.toml", headset_study(kEyesAtDistance));
  const std::string flags = " --observer simulated --gaze synthetic:seed=3";
  const CommandResult paused = run_study(config, "FOVLAB_TEST_XR_UNFOCUS_AT_FRAME=400", FOVLAB_TEST_XR_RUNTIME_JSON,
                                         flags + " --refocus-timeout 1");
  ASSERT_EQ(paused.exit_code, 0) << paused.err;
  EXPECT_NE(paused.out.find("(stopped: the headset session lost focus (XR_SESSION_STATE_VISIBLE)"), std::string::npos)
      << paused.out;
  const std::filesystem::path log = results_ / "headset_cli" / "P01" / "events.jsonl";
  std::ifstream lines(log);
  std::vector<std::string> kinds;
  for (std::string line; std::getline(lines, line);) kinds.push_back(nlohmann::json::parse(line).value("event", ""));
  ASSERT_GE(kinds.size(), 3u);
  EXPECT_EQ(kinds[kinds.size() - 2], "session_paused");
  EXPECT_EQ(kinds.back(), "seal");
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "session_end"), 0);

  const CommandResult resumed = run_study(config, "", FOVLAB_TEST_XR_RUNTIME_JSON, flags);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("resumed, 2 of 2 trials complete"), std::string::npos) << resumed.out;
  const CommandResult replayed = cli_test::run("replay " + log.string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
}

// The plan's stimuli are made for the left eye's image; where the right eye's field of view is
// another size, its sampling maps are checked too: a hyperbolic outer layer beyond a narrow right
// eye's field is refused naming that eye, and accepted where both eyes are wide.
TEST_F(HeadsetStudy, ValidateChecksTheRightEyesMapsWhereItsFieldDiffers) {
  const std::string narrow_right = R"([study]
name = "eyes"
seed = 5

[display]
kind = "openxr"
eye_width_px = 96
eye_height_px = 96
refresh_hz = 90
left_eye_fov_deg = [-54, 49, 54, -56]
right_eye_fov_deg = [-20, 20, 20, -20]

[stimulus]
duration_s = 0.1
frames_per_second = 30

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "hyperbolic"
inner_radius_deg = 5
outer_radius_deg = 30
equalise = "density"

[levels]
parameter = "sigma"
values = [2, 2.6]
higher_is_better = false

[protocol]
kind = "2afc"
question = "same"

[[block]]
scene = "primitives"
)";
  const std::filesystem::path narrow = write("narrow.toml", narrow_right);
  expect_refusal(cli_test::run("validate " + narrow.string() + " --no-render-timing"),
                 narrow.string() +
                     " (right eye): stimulus.test at level 2 (method \"hyperbolic\"): equalise: the "
                     "hyperbolic model cannot reach 1/sigma^2 = 0.25 on this display: no part of it lies "
                     "beyond outer_radius_deg");
  std::string wide_right = narrow_right;
  wide_right.replace(wide_right.find("[-20, 20, 20, -20]"), 18, "[-49, 54, 54, -56]");
  const CommandResult wide =
      cli_test::run("validate " + write("wide.toml", wide_right).string() + " --no-render-timing");
  EXPECT_EQ(wide.exit_code, 0) << wide.err;
}

// The two headset studies in experiments/ pass validate on a machine with no runtime.
TEST(HeadsetExperimentsCli, ValidateAcceptsTheHeadsetStudies) {
  for (const std::string name : {"fipr_main_hmd", "rmfr_sigma_hmd"}) {
    SCOPED_TRACE(name);
    const CommandResult result = cli_test::run(
        "validate " + std::string(FOVLAB_SOURCE_DIR) + "/experiments/" + name + ".toml --no-render-timing",
        "env XR_RUNTIME_JSON=/nonexistent.json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find(": valid\n"), std::string::npos) << result.out;
    EXPECT_NE(result.out.find("display openxr: 1440x1600 px an eye at 90 Hz"), std::string::npos) << result.out;
    EXPECT_NE(result.out.find("  left  eye [-54, 49, 54, -56] deg: 103.0 x 110.0 deg"), std::string::npos)
        << result.out;
  }
}

}  // namespace
}  // namespace fovlab
