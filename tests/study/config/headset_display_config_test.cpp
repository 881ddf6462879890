// [display] kind = "openxr" (study/config/headset_display.h): a headset's keys, each eye's geometry
// in angles, the keys of the other kind refused naming the key and the kind, the per-eye checks, and
// a window config read as before.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <regex>
#include <string>

#include "core/input_error.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "tests/study/config/config_error_test_support.h"

namespace fovlab {
namespace {

const std::string kPath = "studies/headset.toml";

const std::string kStudy = R"([study]
name = "headset"
seed = 3
)";
const std::string kHeadset = R"([display]
kind = "openxr"
eye_width_px = 64
eye_height_px = 72
refresh_hz = 90
left_eye_fov_deg = [-54, 49, 54, -56]
right_eye_fov_deg = [-49, 54, 54, -56]
)";
const std::string kWindow = R"([display]
width_px = 320
height_px = 180
diagonal_in = 27
viewing_distance_mm = 500
)";
const std::string kRest = R"(
[stimulus]
duration_s = 0.5
frames_per_second = 10

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "fipr"

[levels]
parameter = "fovea_radius_deg"
values = [5, 10]

[protocol]
kind = "2afc"
question = "same"

[[block]]
scene = "primitives"
)";

std::string config_with(const std::string& display, const std::string& more = "") {
  return kStudy + display + kRest + more;
}

StudyConfig parse(const std::string& text) { return parse_study_config_text(text, kPath, renderer_scene_catalog()); }

using test::line_of;

// One line "studies/headset.toml:LINE: KEY: ..." containing `fragment`.
void expect_error(const std::string& text, int line, const std::string& key, const std::string& fragment) {
  test::expect_config_error(text, kPath, line, key, fragment);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

double tan_deg(double degrees) { return std::tan(degrees * std::numbers::pi / 180.0); }

TEST(HeadsetDisplayConfig, ReadsEachEyesSizeAndAnglesWithTheDefaults) {
  const StudyConfig config = parse(config_with(kHeadset));
  const DisplayConfig& display = config.display;
  EXPECT_EQ(display.kind, DisplayKind::openxr);
  EXPECT_EQ(display.headset.eye_width_px, 64);
  EXPECT_EQ(display.headset.eye_height_px, 72);
  EXPECT_EQ(display.headset.eye_size_line, line_of(config_with(kHeadset), "eye_width_px"));
  EXPECT_EQ(display.refresh_hz, 90.0);
  EXPECT_EQ(display.headset.left_eye_fov, field_of_view_from_deg(-54.0, 49.0, 54.0, -56.0));
  EXPECT_EQ(display.headset.right_eye_fov, field_of_view_from_deg(-49.0, 54.0, 54.0, -56.0));
  EXPECT_EQ(display.headset.ipd_mm, 63.0);
  EXPECT_EQ(display.headset.view_model, HeadsetViewModel::head_locked);
  EXPECT_EQ(display.headset.gaze_fixation, GazeFixation::rendered_depth);
  // The plan's stimuli: each eye's size, for the left eye's image plane 1 m away.
  EXPECT_EQ(display.width_px, 64);
  EXPECT_EQ(display.height_px, 72);
  EXPECT_DOUBLE_EQ(display.viewing_distance_mm, 1000.0);
  EXPECT_NEAR(display.width_mm, 1000.0 * (tan_deg(49) + tan_deg(54)), 1e-9);
  EXPECT_NEAR(display.height_mm, 1000.0 * (tan_deg(54) + tan_deg(56)), 1e-9);
  EXPECT_EQ(config.stimulus.frames_per_second, 10.0);

  const std::string chosen =
      replaced(kHeadset, "refresh_hz = 90\n",
               "refresh_hz = 120\nipd_mm = 58.5\nview_model = \"head-tracked\"\nfixation_distance_mm = 750\n");
  const HeadsetDisplayConfig& headset = parse(config_with(chosen)).display.headset;
  EXPECT_EQ(headset.ipd_mm, 58.5);
  EXPECT_EQ(headset.view_model, HeadsetViewModel::head_tracked);
  EXPECT_EQ(headset.gaze_fixation, GazeFixation::fixation_distance);  // fixation_distance_mm implies it
  EXPECT_EQ(headset.fixation_distance_mm, 750.0);
  const std::string both =
      replaced(chosen, "fixation_distance_mm", "gaze_fixation = \"fixation-distance\"\nfixation_distance_mm");
  EXPECT_EQ(parse(config_with(both)).display.headset.gaze_fixation, GazeFixation::fixation_distance);
}

// "The runtime's recommended size" (0) is refused as the config is read, for every command: the
// stimuli, their pre-rendered frames and the thresholds hold for one size, every participant's.
TEST(HeadsetDisplayConfig, RefusesTheRuntimesRecommendedSizeNamingFovlabDevices) {
  const std::string recommended =
      replaced(replaced(kHeadset, "eye_width_px = 64", "eye_width_px = 0"), "eye_height_px = 72", "eye_height_px = 0");
  const std::string text = config_with(recommended);
  expect_error(text, line_of(text, "eye_width_px"), "display.eye_width_px",
               "expected each eye's size in pixels, 8..16384, one size for every participant of the study "
               "(`fovlab devices` prints the runtime's recommended size), got 0");
  const std::string height_only = config_with(replaced(kHeadset, "eye_height_px = 72", "eye_height_px = 0"));
  expect_error(height_only, line_of(height_only, "eye_height_px"), "display.eye_height_px", "got 0");
}

TEST(HeadsetDisplayConfig, WindowIsTheDefaultKindAndReadsAsBefore) {
  const StudyConfig plain = parse(config_with(kWindow));
  EXPECT_EQ(plain.display.kind, DisplayKind::window);
  EXPECT_EQ(plain.display.width_px, 320);
  EXPECT_NEAR(plain.display.width_mm, 27 * 25.4 * 320 / std::hypot(320.0, 180.0), 1e-9);
  const StudyConfig named = parse(config_with(replaced(kWindow, "[display]\n", "[display]\nkind = \"window\"\n")));
  EXPECT_EQ(named.display.kind, DisplayKind::window);
  EXPECT_EQ(named.display.width_mm, plain.display.width_mm);
  EXPECT_NE(named.content_hash, plain.content_hash);  // what the text says: a key more
}

TEST(HeadsetDisplayConfig, KeysOfTheOtherKindAreRefusedNamingTheKeyAndTheKind) {
  for (const std::string headset_key :
       {"eye_width_px = 64", "left_eye_fov_deg = [-50, 50, 50, -50]", "ipd_mm = 63", "view_model = \"head-locked\"",
        "gaze_fixation = \"rendered-depth\"", "fixation_distance_mm = 800"}) {
    const std::string text = config_with(kWindow + headset_key + "\n");
    const std::string key = headset_key.substr(0, headset_key.find(' '));
    expect_error(text, line_of(text, headset_key), "display." + key,
                 "a key of [display] kind = \"openxr\" (a headset); this [display] is kind \"window\"");
  }
  for (const std::string window_key : {"width_px = 320", "height_px = 180", "width_mm = 600", "height_mm = 340",
                                       "diagonal_in = 27", "viewing_distance_mm = 500", "fullscreen = true"}) {
    const std::string text = config_with(kHeadset + window_key + "\n");
    const std::string key = window_key.substr(0, window_key.find(' '));
    expect_error(text, line_of(text, window_key), "display." + key, "not a key of [display] kind = \"openxr\"");
  }
  const std::string other = config_with(replaced(kHeadset, "kind = \"openxr\"", "kind = \"hmd\""));
  expect_error(other, line_of(other, "kind = \"hmd\""), "display.kind",
               "expected \"window\" (a desktop window, the default) or \"openxr\"");
  const std::string unknown = config_with(kHeadset + "eye_gap_mm = 3\n");
  expect_error(unknown, line_of(unknown, "eye_gap_mm"), "display.eye_gap_mm", "unknown key");
}

TEST(HeadsetDisplayConfig, RefusesBadSizesAnglesAndChoicesInOneLine) {
  const auto expect_refused = [](const std::string& from, const std::string& to, const std::string& key,
                                 const std::string& fragment) {
    const std::string text = config_with(replaced(kHeadset, from, to));
    SCOPED_TRACE(to);
    expect_error(text, line_of(text, key + " ="), "display." + key, fragment);
  };
  expect_refused("eye_width_px = 64", "eye_width_px = 4", "eye_width_px",
                 "expected each eye's size in pixels, 8..16384");
  expect_refused("eye_width_px = 64", "eye_width_px = 20000", "eye_width_px", "expected a value in [0, 16384]");
  const std::string fov = "left_eye_fov_deg = [-54, 49, 54, -56]";
  expect_refused(fov, "left_eye_fov_deg = [-54, 49, 54]", "left_eye_fov_deg", "got 3 numbers");
  expect_refused(fov, "left_eye_fov_deg = [-90, 49, 54, -56]", "left_eye_fov_deg", "each within (-90, 90)), got -90");
  expect_refused(fov, "left_eye_fov_deg = [5, 49, 54, -56]", "left_eye_fov_deg", "got left 5 and right 49");
  expect_refused("right_eye_fov_deg = [-49, 54, 54, -56]", "right_eye_fov_deg = [-49, 54, -5, -56]",
                 "right_eye_fov_deg", "got up -5 and down -56");
  expect_refused(fov, "left_eye_fov_deg = \"wide\"", "left_eye_fov_deg", "");
  expect_refused("refresh_hz = 90", "refresh_hz = 0.5", "refresh_hz", "expected a value in [1, 1000]");
  expect_refused("refresh_hz = 90", "refresh_hz = 90\nipd_mm = 20", "ipd_mm", "expected a value in [40, 90]");
  expect_refused("refresh_hz = 90", "refresh_hz = 90\nview_model = \"free\"", "view_model",
                 "expected \"head-locked\" (the default) or \"head-tracked\"");
  expect_refused("refresh_hz = 90", "refresh_hz = 90\ngaze_fixation = \"fixation-distance\"", "gaze_fixation",
                 "needs fixation_distance_mm");
  expect_refused("refresh_hz = 90", "refresh_hz = 90\ngaze_fixation = \"vergence\"", "gaze_fixation",
                 "expected \"rendered-depth\" (the default) or \"fixation-distance\"");
  expect_refused("refresh_hz = 90", "refresh_hz = 90\nfixation_distance_mm = 10", "fixation_distance_mm",
                 "expected a value in [100, 1e+06]");
  const std::string conflicting =
      config_with(kHeadset + "gaze_fixation = \"rendered-depth\"\nfixation_distance_mm = 800\n");
  expect_error(conflicting, line_of(conflicting, "fixation_distance_mm"), "display.fixation_distance_mm",
               "not with gaze_fixation = \"rendered-depth\"");
  const std::string missing = config_with(replaced(kHeadset, "refresh_hz = 90\n", ""));
  expect_error(missing, line_of(missing, "[display]"), "display.refresh_hz", "");
  // The renderers' frame size rule names the eye's keys.
  const std::string large = config_with(replaced(replaced(kHeadset, "eye_width_px = 64", "eye_width_px = 8192"),
                                                 "eye_height_px = 72", "eye_height_px = 8192"));
  const std::string supersampled = replaced(large, "[stimulus.test]\nmethod = \"fipr\"",
                                            "[stimulus.test]\nmethod = \"fipr\"\nsamples_per_pixel = 16");
  expect_error(supersampled, line_of(supersampled, "eye_width_px"), "display.eye_width_px",
               "expected eye_width_px x eye_height_px x samples_per_pixel of at most");
}

// validation targets at +-offset deg from each eye's forward direction must be inside each eye's
// field of view: the narrower side of either eye decides.
TEST(HeadsetDisplayConfig, ValidationTargetsMustFitEachEyesFieldOfView) {
  const std::string validation = "\n[validation]\ntarget_offset_deg = 40\n";
  EXPECT_TRUE(parse(config_with(kHeadset, validation)).validation.enabled);  // 40.3 < 49
  const std::string narrow =
      replaced(kHeadset, "right_eye_fov_deg = [-49, 54, 54, -56]", "right_eye_fov_deg = [-38, 54, 54, -56]");
  const std::string text = config_with(narrow, validation);
  expect_error(text, line_of(text, "target_offset_deg"), "validation.target_offset_deg",
               "expected targets in each eye's field of view: at 40 deg the outer ones fall outside the right eye's "
               "[-38, 54, 54, -56] deg");
  // The disk counts: 39.8 + 0.3 reaches past 40.
  const std::string edge = replaced(narrow, "[-38, 54, 54, -56]", "[-40, 54, 54, -56]");
  EXPECT_NO_THROW(parse(config_with(edge, "\n[validation]\ntarget_offset_deg = 39.6\n")));
  EXPECT_THROW(parse(config_with(edge, "\n[validation]\ntarget_offset_deg = 39.8\n")), InputError);
}

// Each eye's geometry from its angles: at +-45 deg the image plane spans [-1, 1] at unit distance,
// so a radian at the centre covers half the image.
TEST(EyeViewGeometry, PixelsPerDegreeAndCentreFromTheImagePlane) {
  const EyeViewGeometry square = eye_view_geometry(field_of_view_from_deg(-45, 45, 45, -45), 1000, 800);
  EXPECT_NEAR(square.centre_x_px, 500.0, 1e-9);
  EXPECT_NEAR(square.centre_y_px, 400.0, 1e-9);
  EXPECT_NEAR(square.pixels_per_degree_x, 500.0 * std::numbers::pi / 180.0, 1e-9);
  EXPECT_NEAR(square.pixels_per_degree_y, 400.0 * std::numbers::pi / 180.0, 1e-9);
  EXPECT_NEAR(square.width_deg, 90.0, 1e-12);
  // Off-axis: [-45, 0+, ...]: the forward direction meets the image near its right edge.
  const EyeViewGeometry off_axis = eye_view_geometry(field_of_view_from_deg(-45, 26.565051177077990, 45, -45), 300, 200);
  EXPECT_NEAR(off_axis.centre_x_px, 200.0, 1e-9);  // tan 26.57 deg = 0.5: the plane is [-1, 0.5]
  EXPECT_NEAR(off_axis.pixels_per_degree_x, 200.0 * std::numbers::pi / 180.0, 1e-9);
  EXPECT_NEAR(off_axis.width_deg, 71.565051177077990, 1e-12);
  // Directions: the four angles reach the image's edges, the forward direction its centre.
  const auto [right_x, up_y] = eye_pixel_of_direction(off_axis, 26.565051177077990, 45);
  EXPECT_NEAR(right_x, 300.0, 1e-9);
  EXPECT_NEAR(up_y, 0.0, 1e-9);
  const auto [left_x, down_y] = eye_pixel_of_direction(off_axis, -45, -45);
  EXPECT_NEAR(left_x, 0.0, 1e-9);
  EXPECT_NEAR(down_y, 200.0, 1e-9);
  const auto [forward_x, forward_y] = eye_pixel_of_direction(off_axis, 0, 0);
  EXPECT_NEAR(forward_x, off_axis.centre_x_px, 1e-9);
  EXPECT_NEAR(forward_y, off_axis.centre_y_px, 1e-9);
  EXPECT_EQ(field_of_view_text(field_of_view_from_deg(-54, 49, 54, -56.5)), "[-54, 49, 54, -56.5] deg");
}

// The headset versions of the two headset studies: the Vive Pro Eye's size and rate, the protocol of
// their desktop versions.
TEST(HeadsetExperiments, TheHeadsetStudiesAreTheirDesktopVersionsInTheHeadset) {
  for (const std::string name : {"fipr_main", "rmfr_sigma"}) {
    SCOPED_TRACE(name);
    const std::string experiments = std::string(FOVLAB_SOURCE_DIR) + "/experiments/";
    const StudyConfig desktop = parse_study_config_file(experiments + name + ".toml", renderer_scene_catalog());
    const StudyConfig headset = parse_study_config_file(experiments + name + "_hmd.toml", renderer_scene_catalog());
    EXPECT_EQ(headset.display.kind, DisplayKind::openxr);
    EXPECT_EQ(headset.display.headset.eye_width_px, 1440);
    EXPECT_EQ(headset.display.headset.eye_height_px, 1600);
    EXPECT_EQ(headset.display.refresh_hz, 90.0);
    EXPECT_EQ(headset.name, name + "_hmd");
    EXPECT_EQ(headset.stimulus.reference.method, desktop.stimulus.reference.method);
    EXPECT_EQ(headset.stimulus.test.method, desktop.stimulus.test.method);
    EXPECT_EQ(headset.stimulus.test.parameters, desktop.stimulus.test.parameters);
    EXPECT_EQ(headset.stimulus.variants.size(), desktop.stimulus.variants.size());
    EXPECT_EQ(headset.stimulus.duration_s, desktop.stimulus.duration_s);
    EXPECT_EQ(headset.stimulus.frames_per_second, desktop.stimulus.frames_per_second);
    EXPECT_EQ(headset.levels.values, desktop.levels.values);
    EXPECT_EQ(headset.protocol.kind, desktop.protocol.kind);
    EXPECT_EQ(headset.protocol.repeats, desktop.protocol.repeats);
    EXPECT_EQ(headset.attention.share, desktop.attention.share);
    EXPECT_EQ(headset.timing.black_interval_s, desktop.timing.black_interval_s);
    EXPECT_EQ(headset.timing.rest_between_blocks_s, desktop.timing.rest_between_blocks_s);
    ASSERT_EQ(headset.blocks.size(), desktop.blocks.size());
    for (size_t i = 0; i < headset.blocks.size(); ++i) EXPECT_EQ(headset.blocks[i].scene, desktop.blocks[i].scene);
  }
}

}  // namespace
}  // namespace fovlab
