// Head-tracked views in a headset session (issue 42, docs/hmd.md): `view_model = "head-tracked"`
// renders each refresh of both eyes from the head's pose relative to the session's start, logs that
// pose (head_pose) and replays from it. The runtime is the test runtime (tests/xr_runtime) in a child
// process, its head turned and moved at constant rates by FOVLAB_TEST_XR_HEAD, with the OpenXR core
// validation layer on (its file must stay empty). Also the pose arithmetic itself, against hand values.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/eye_field_of_view.h"
#include "core/input_error.h"
#include "protocols/session/head_tracking.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/present/device_frame.h"
#include "renderer/scene/eye_view.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "study/config/study_config.h"
#include "study/log/log_events.h"
#include "study/schedule/study_plan.h"
#include "tests/app/cli_test_support.h"
#include "tests/display/openxr/openxr_test_support.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using cli_test::CommandResult;

// The test runtime's line at load is no message of fovlab's (as in openxr_study_cli_test.cpp).
void expect_refusal(CommandResult result, const std::string& must_contain) {
  const std::string layer_line = "Core Validation output type: ";
  for (size_t at; (at = result.err.find(layer_line)) != std::string::npos;)
    result.err.erase(at, result.err.find('\n', at) + 1 - at);
  cli_test::expect_one_line_error(result, must_contain);
}

// GT against IPR at 64x72 an eye, 3 animation frames of 3 refreshes each at 90 Hz; `view_model` and
// the methods as given.
std::string tracked_study(const std::string& view_model = "head-tracked", const std::string& reference = "gt",
                          const std::string& test = "ipr",
                          const std::string& levels = "parameter = \"max_steps\"\nvalues = [4, 8]",
                          const std::string& scene = "primitives") {
  return R"([study]
name = "head_tracked"
seed = 5

[display]
kind = "openxr"
eye_width_px = 64
eye_height_px = 72
gaze_fixation = "fixation-distance"
fixation_distance_mm = 1500
view_model = ")" + view_model + R"("
refresh_hz = 90
left_eye_fov_deg = [-54, 49, 54, -56]
right_eye_fov_deg = [-49, 54, 54, -56]

[stimulus]
duration_s = 0.1
frames_per_second = 30

[stimulus.reference]
method = ")" + reference + R"("

[stimulus.test]
method = ")" + test + R"("

[levels]
)" + levels + R"(

[protocol]
kind = "2afc"
question = "same"

[[block]]
scene = ")" + scene + "\"\n";
}

// The scripted head: turning right, and moving right along LOCAL's x (slow enough that a session of a
// few seconds keeps the scene in view and the turn under half a revolution).
constexpr double kYawDegPerS = 10.0;
constexpr double kXMPerS = 0.3;
const std::string kMovingHead = "FOVLAB_TEST_XR_HEAD=10,0.3";

using Pose = std::array<double, 7>;  // a head_pose entry: x, y, z, qx, qy, qz, qw

struct StimulusShown {
  int stimulus = -1;
  std::vector<int> frame;
  std::vector<double> present_s;
  std::vector<std::string> hash, right_eye_hash;
  std::vector<Pose> head_pose;  // empty when the event has none
};

struct SessionLog {
  nlohmann::json header;
  std::vector<StimulusShown> stimuli;
};

SessionLog read_session(const std::filesystem::path& log) {
  SessionLog session;
  std::ifstream lines(log);
  std::string line;
  while (std::getline(lines, line)) {
    const nlohmann::json event = nlohmann::json::parse(line);
    if (event.value("event", "") == "session_header") session.header = event;
    if (event.value("event", "") != "stimulus") continue;
    StimulusShown shown;
    shown.stimulus = event["stimulus"].get<int>();
    shown.frame = event["frame"].get<std::vector<int>>();
    shown.present_s = event["present_s"].get<std::vector<double>>();
    shown.hash = event["hash"].get<std::vector<std::string>>();
    shown.right_eye_hash = event["right_eye_hash"].get<std::vector<std::string>>();
    if (event.contains("head_pose")) shown.head_pose = event["head_pose"].get<std::vector<Pose>>();
    session.stimuli.push_back(shown);
  }
  return session;
}

class HeadTrackedStudy : public test::OpenXrTest {
 protected:
  std::filesystem::path write(const std::string& name, const std::string& text) {
    return cli_test::write_file(scratch_.path() / name, text);
  }
  CommandResult run_study(const std::filesystem::path& config, const std::string& switches,
                          const std::filesystem::path& results) {
    return cli_test::run("run " + config.string() + " --participant P01 --results " + results.string() +
                             " --observer simulated --gaze synthetic:seed=3",
                         child_environment(FOVLAB_TEST_XR_RUNTIME_JSON) + " " + switches);
  }
  std::filesystem::path log_in(const std::filesystem::path& results) const {
    return results / "head_tracked" / "P01" / "events.jsonl";
  }
};

// The turn (degrees, right positive) of a head pose that turns about y only.
double yaw_deg(const Pose& pose) { return -2.0 * std::atan2(pose[4], pose[6]) * 180.0 / std::numbers::pi; }

// The eye where the logged head carries it, by hand: the eye's offset turned by the head's quaternion
// (q p q*), then moved by the head's position; the orientations multiplied head first.
EyeView eye_carried_by_hand(const nlohmann::json& eye_json, const Pose& head) {
  using Q = std::array<double, 4>;
  const auto times = [](const Q& a, const Q& b) {
    return Q{a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],  //
             a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],  //
             a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],  //
             a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
  };
  const std::array<double, 3> p = eye_json["position_m"].get<std::array<double, 3>>();
  const Q eye_q = eye_json["orientation"].get<Q>();
  const std::array<double, 4> fov = eye_json["fov_rad"].get<std::array<double, 4>>();
  const Q q{head[3], head[4], head[5], head[6]};
  const Q turned = times(times(q, {p[0], p[1], p[2], 0.0}), {-q[0], -q[1], -q[2], q[3]});
  EyeView eye;
  eye.position_in_head = {head[0] + turned[0], head[1] + turned[1], head[2] + turned[2]};
  eye.orientation_in_head = times(q, eye_q);
  eye.field_of_view = {fov[0], fov[1], fov[2], fov[3]};
  return eye;
}

// A moving head: each refresh's pose is logged as the script moves it (the turn and the travel in
// the ratio of their rates, the turn between refreshes the rate times the time between them), every
// refresh is a new frame, the log replays both eyes to their hashes, and a logged frame is the
// renderer's own offscreen frame of the eye carried by the logged pose.
TEST_F(HeadTrackedStudy, AMovingHeadIsLoggedEachRefreshRenderedFromAndReplayed) {
  const std::filesystem::path config = write("moving.toml", tracked_study());
  const std::filesystem::path results = scratch_.path() / "moving";
  const CommandResult ran = run_study(config, kMovingHead, results);
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  const SessionLog session = read_session(log_in(results));
  EXPECT_GE(session.header.value("schema_version", 0), 12);  // head_pose and head_reference since 12
  const nlohmann::json& headset = session.header["headset"];
  EXPECT_EQ(headset.value("view_model", ""), "head-tracked");
  ASSERT_TRUE(headset.contains("head_reference")) << headset.dump();
  // The reference is where the head was at the start, already turned right by then.
  const std::array<double, 4> reference_q = headset["head_reference"]["orientation"].get<std::array<double, 4>>();
  EXPECT_LT(reference_q[1], 0.0) << headset.dump();
  ASSERT_EQ(session.stimuli.size(), 4u);  // 2 trials of 2
  for (const StimulusShown& shown : session.stimuli) {
    ASSERT_EQ(shown.head_pose.size(), shown.hash.size());
    ASSERT_EQ(shown.hash.size(), 9u);
    for (size_t i = 0; i < shown.head_pose.size(); ++i) {
      const Pose& pose = shown.head_pose[i];
      // A turn about y only, right; the travel along the start's right and forward axes only.
      EXPECT_EQ(pose[3], 0.0);
      EXPECT_EQ(pose[5], 0.0);
      EXPECT_EQ(pose[1], 0.0);
      const double yaw = yaw_deg(pose);
      EXPECT_GT(yaw, 0.0);
      EXPECT_NEAR(std::hypot(pose[0], pose[2]), yaw / kYawDegPerS * kXMPerS, 2e-5) << "the travel and the turn";
      // Each logged number is on the log's grid (kHeadPoseStep).
      for (const double value : pose) EXPECT_NEAR(value * 1e6, std::round(value * 1e6), 1e-6) << value;
      if (i == 0) continue;
      const double elapsed_s = shown.present_s[i] - shown.present_s[i - 1];
      EXPECT_NEAR(yaw - yaw_deg(shown.head_pose[i - 1]), kYawDegPerS * elapsed_s, 1e-3) << "refresh " << i;
      EXPECT_NE(shown.hash[i], shown.hash[i - 1]) << "the head moved, the frame did not (left eye, refresh " << i
                                                  << ")";
      EXPECT_NE(shown.right_eye_hash[i], shown.right_eye_hash[i - 1]) << "right eye, refresh " << i;
    }
  }
  const CommandResult replayed = cli_test::run("replay " + log_in(results).string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
  EXPECT_NE(replayed.out.find("replay matches the log"), std::string::npos) << replayed.out;

  // The GT stimulus's fifth refresh, each eye, rendered here through the tracer from the logged pose.
  const StudyConfig parsed = parse_study_config_file(config.string(), renderer_scene_catalog());
  const StudyPlan plan = make_study_plan(parsed, "P01");
  const StimulusShown* gt = nullptr;
  for (const StimulusShown& shown : session.stimuli)
    if (plan.stimuli.at(size_t(shown.stimulus)).spec.method() == RenderMethod::ground_truth) gt = &shown;
  ASSERT_NE(gt, nullptr);
  const StimulusSpec& spec = plan.stimuli.at(size_t(gt->stimulus)).spec;
  vk::Context& context = test::shared_context();
  const size_t messages_before = context.validation_message_count();
  SphereTracer tracer(context, load_scene(spec.scene));
  const size_t refresh = 4;
  for (size_t eye = 0; eye < 2; ++eye) {
    SphereTraceSettings settings = sphere_trace_settings(spec, gt->frame[refresh]);
    settings.eye = eye_carried_by_hand(headset["eyes"][eye], gt->head_pose[refresh]);
    settings.outputs = TraceOutputs::display;
    const std::string offscreen = frame_hash(read_back(tracer.render(settings).display));
    EXPECT_EQ(offscreen, (eye == 0 ? gt->hash : gt->right_eye_hash)[refresh]) << "eye " << eye;
    // The check can fail: the head-locked eye's frame is another.
    settings.eye = eye_carried_by_hand(headset["eyes"][eye], Pose{0, 0, 0, 0, 0, 0, 1});
    EXPECT_NE(frame_hash(read_back(tracer.render(settings).display)), offscreen) << "eye " << eye;
  }
  EXPECT_EQ(context.validation_message_count(), messages_before) << "Vulkan validation messages";
}

// A still head: every logged pose is the start's, and the frames are the head-locked session's own.
TEST_F(HeadTrackedStudy, AStillHeadShowsTheHeadLockedFrames) {
  const std::filesystem::path tracked = scratch_.path() / "tracked", locked = scratch_.path() / "locked";
  ASSERT_EQ(run_study(write("tracked.toml", tracked_study()), "", tracked).exit_code, 0);
  ASSERT_EQ(run_study(write("locked.toml", tracked_study("head-locked")), "", locked).exit_code, 0);
  const SessionLog still = read_session(log_in(tracked)), head_locked = read_session(log_in(locked));
  EXPECT_FALSE(head_locked.header["headset"].contains("head_reference"));
  ASSERT_EQ(still.stimuli.size(), head_locked.stimuli.size());
  ASSERT_EQ(still.stimuli.size(), 4u);
  for (size_t s = 0; s < still.stimuli.size(); ++s) {
    EXPECT_TRUE(head_locked.stimuli[s].head_pose.empty()) << "a head-locked session logs no head_pose";
    ASSERT_EQ(still.stimuli[s].head_pose.size(), still.stimuli[s].hash.size());
    for (const Pose& pose : still.stimuli[s].head_pose) EXPECT_EQ(pose, (Pose{0, 0, 0, 0, 0, 0, 1}));
    EXPECT_EQ(still.stimuli[s].stimulus, head_locked.stimuli[s].stimulus);
    EXPECT_EQ(still.stimuli[s].hash, head_locked.stimuli[s].hash) << "stimulus event " << s;
    EXPECT_EQ(still.stimuli[s].right_eye_hash, head_locked.stimuli[s].right_eye_hash) << "stimulus event " << s;
  }
  const CommandResult replayed = cli_test::run("replay " + log_in(tracked).string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
}

// What cannot follow a head is refused in one line naming display.view_model, before a results
// folder exists: pre-rendered path-traced frames (fpt). A malformed head script fails the session.
TEST_F(HeadTrackedStudy, RefusesStimuliThatCannotFollowTheHead) {
  const std::filesystem::path results = scratch_.path() / "refused";
  const std::filesystem::path fpt = write(
      "fpt.toml", tracked_study("head-tracked", "pt", "fpt", "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]",
                                "courtyard"));
  expect_refusal(run_study(fpt, "", results),
                 fpt.string() + ": display.view_model: \"head-tracked\" renders every refresh anew from the head's "
                                "pose, and method ");
  EXPECT_FALSE(std::filesystem::exists(results / "head_tracked" / "P01" / "events.jsonl"));
}

// The same line from every command that reads a study config (the check is where the config is
// read), for pre-rendered path-traced frames and for images; head-locked, neither is refused for it.
TEST_F(HeadTrackedStudy, EveryCommandRefusesStimuliThatCannotFollowTheHead) {
  const std::string levels = "parameter = \"foveal_aperture_deg\"\nvalues = [5, 20]";
  const std::filesystem::path fpt = write("fpt.toml", tracked_study("head-tracked", "pt", "fpt", levels, "courtyard"));
  const std::string in_scratch = "cd " + scratch_.path().string() + " &&";  // prerender's cache is beside it
  const std::string refusal =
      ": display.view_model: \"head-tracked\" renders every refresh anew from the head's pose, and method ";
  for (const std::string command : {"validate --no-render-timing ", "simulate --participants 1 ", "prerender "}) {
    SCOPED_TRACE(command);
    expect_refusal(cli_test::run(command + fpt.string(), in_scratch),
                   fpt.string() + refusal + "pt (path-traced) shows frames");
  }
  expect_refusal(cli_test::run("bench --headset " + fpt.string(), in_scratch), fpt.string() + refusal);

  std::filesystem::create_directories(scratch_.path() / "images");
  const std::string image_levels = "parameter = \"sigma\"\nvalues = [2, 3]";
  const std::filesystem::path images =
      write("images.toml", tracked_study("head-tracked", "img-rmfr", "img-rmfr", image_levels, "images"));
  expect_refusal(cli_test::run("validate --no-render-timing " + images.string(), in_scratch),
                 images.string() + refusal + "img-rmfr (image-sequence) shows frames");

  // The check can fail: head-locked, validate accepts the fpt study, and the image study gets past
  // the view model to the next check (its folder holds no image yet).
  const std::filesystem::path fpt_locked =
      write("fpt_locked.toml", tracked_study("head-locked", "pt", "fpt", levels, "courtyard"));
  const CommandResult validated = cli_test::run("validate --no-render-timing " + fpt_locked.string(), in_scratch);
  EXPECT_EQ(validated.exit_code, 0) << validated.err;
  const CommandResult images_locked = cli_test::run(
      "validate --no-render-timing " +
          write("images_locked.toml", tracked_study("head-locked", "img-rmfr", "img-rmfr", image_levels, "images"))
              .string(),
      in_scratch);
  EXPECT_NE(images_locked.err.find("no .png or .exr image in it"), std::string::npos) << images_locked.err;
}

// Volumes follow the head too (the raycaster renders each refresh from the carried eye).
TEST_F(HeadTrackedStudy, AVolumeStudyFollowsTheHeadAndReplays) {
  const std::filesystem::path config =
      write("volume.toml", tracked_study("head-tracked", "volume", "fvolume",
                                         "parameter = \"density_sigma_deg\"\nvalues = [0.5, 3.0]", "shepp-logan"));
  const std::filesystem::path results = scratch_.path() / "volume";
  const CommandResult ran = run_study(config, kMovingHead, results);
  ASSERT_EQ(ran.exit_code, 0) << ran.err;
  const SessionLog session = read_session(log_in(results));
  ASSERT_FALSE(session.stimuli.empty());
  for (const StimulusShown& shown : session.stimuli) {
    ASSERT_EQ(shown.head_pose.size(), shown.hash.size());
    EXPECT_NE(shown.head_pose.front(), shown.head_pose.back());
  }
  const CommandResult replayed = cli_test::run("replay " + log_in(results).string() + " --verify");
  EXPECT_EQ(replayed.exit_code, 0) << replayed.out << replayed.err;
}

// A head-tracked eye's library: every image is rendered from its head (nothing taken from frames made
// ahead), the start's pose gives the head-locked frame, another pose the frame of the eye it carries;
// stimuli made ahead for one view (path-traced) are refused naming display.view_model.
class HeadTrackedLibrary : public test::VulkanTest {};

TEST_F(HeadTrackedLibrary, RendersEachImageFromItsHeadAndRefusesFramesMadeAhead) {
  StimulusSpec spec;
  spec.scene = "primitives";
  spec.parameters = default_parameters(RenderMethod::ground_truth);
  spec.width_px = 48;
  spec.height_px = 40;
  spec.frame_count = 1;
  spec.camera_start_s = 1.5;
  EyeView eye;
  eye.position_in_head = {-0.0315, 0.0, 0.0};
  eye.field_of_view = field_of_view_from_deg(-30.0, 22.0, 24.0, -27.0);
  StimulusLibrary tracked(context(), "stimuli/cache", eye, true);
  tracked.prepare({{0, spec}});
  StimulusImage still, turned;
  still.head = HeadPose{};
  const double half_turn_rad = -5.0 * std::numbers::pi / 180.0;  // 10 degrees right
  turned.head = HeadPose{{0.05, 0.0, 0.0}, {0.0, std::sin(half_turn_rad), 0.0, std::cos(half_turn_rad)}};
  const std::string still_hash = tracked.hash(tracked.frame(0, spec, still));
  const std::string turned_hash = tracked.hash(tracked.frame(0, spec, turned));
  EXPECT_NE(still_hash, turned_hash);
  StimulusLibrary locked(context(), "stimuli/cache", eye);
  locked.prepare({{0, spec}});
  EXPECT_EQ(locked.frame(0, spec, StimulusImage{}).hash, still_hash);
  StimulusLibrary carried(context(), "stimuli/cache", eye_view_in_moved_head(eye, *turned.head));
  EXPECT_EQ(carried.render(spec, StimulusImage{}).hash, turned_hash);

  StimulusSpec pt = spec;
  pt.scene = "courtyard";
  pt.parameters = default_parameters(RenderMethod::path_traced);
  try {
    tracked.prepare({{1, pt}});
    ADD_FAILURE() << "a path-traced stimulus was not refused";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("display.view_model: a \"head-tracked\" study re-renders"),
              std::string::npos)
        << error.what();
  }
}

// The pose arithmetic against hand values: the head turned 90 degrees right and moved 0.1 m right;
// the left eye 31.5 mm left of the head and turned 10 degrees up.
TEST(HeadTrackedPose, AnEyeIsTurnedByTheHeadThenMovedWithIt) {
  const double s = std::sqrt(0.5);
  const HeadPose head{{0.1, 0.0, 0.0}, {0.0, -s, 0.0, s}};  // 90 degrees right: -z turns to +x
  EyeView eye;
  eye.position_in_head = {-0.0315, 0.0, 0.0};
  const double up = 5.0 * std::numbers::pi / 180.0;  // half of 10 degrees about +x (up)
  eye.orientation_in_head = {std::sin(up), 0.0, 0.0, std::cos(up)};
  eye.field_of_view = field_of_view_from_deg(-54.0, 49.0, 54.0, -56.0);
  const EyeView moved = eye_view_in_moved_head(eye, head);
  // Turned first: the head's right (+x) now points backwards (+z), so the eye's offset left is
  // forward (-z); then moved by the head's 0.1 m. (Moving first, then turning, would put it at +z.)
  EXPECT_NEAR(moved.position_in_head[0], 0.1, 1e-12);
  EXPECT_NEAR(moved.position_in_head[1], 0.0, 1e-12);
  EXPECT_NEAR(moved.position_in_head[2], -0.0315, 1e-12);
  // head * eye: (0, -s, 0, s) * (sin u, 0, 0, cos u) = (s sin u, -s cos u, s sin u, s cos u).
  EXPECT_NEAR(moved.orientation_in_head[0], s * std::sin(up), 1e-12);
  EXPECT_NEAR(moved.orientation_in_head[1], -s * std::cos(up), 1e-12);
  EXPECT_NEAR(moved.orientation_in_head[2], s * std::sin(up), 1e-12);
  EXPECT_NEAR(moved.orientation_in_head[3], s * std::cos(up), 1e-12);
  EXPECT_EQ(moved.field_of_view, eye.field_of_view);
  // The start's pose gives the eye back bit for bit.
  EXPECT_EQ(eye_view_in_moved_head(eye, HeadPose{}), eye);
}

TEST(HeadTrackedPose, APoseRelativeToTheReferenceIsInTheReferencesAxes) {
  const double s = std::sqrt(0.5);
  const HeadPose reference{{1.0, 0.0, 0.0}, {0.0, -s, 0.0, s}};   // 90 degrees right, at x = 1
  const HeadPose now{{1.0, 0.0, -0.2}, {0.0, -1.0, 0.0, 0.0}};     // 180 degrees, 0.2 m along -z
  const HeadPose delta = head_pose_relative_to(reference, now);
  // LOCAL's -z is the reference's left (-x): 0.2 m left; and 90 degrees more to the right.
  EXPECT_NEAR(delta.position_m[0], -0.2, 1e-12);
  EXPECT_NEAR(delta.position_m[1], 0.0, 1e-12);
  EXPECT_NEAR(delta.position_m[2], 0.0, 1e-12);
  EXPECT_NEAR(delta.orientation[1], -s, 1e-12);
  EXPECT_NEAR(delta.orientation[3], s, 1e-12);
  // The gaze ray's origin and direction in the head now, in the start's axes.
  const std::array<double, 3> point = point_in_start_head(delta, {0.0, 0.0, -1.0});
  EXPECT_NEAR(point[0], 0.8, 1e-12);
  EXPECT_NEAR(point[2], 0.0, 1e-12);
  const std::array<double, 3> direction = direction_in_start_head(delta, {0.0, 0.0, -1.0});
  EXPECT_NEAR(direction[0], 1.0, 1e-12);
}

// What the compositor is told an eye's image was rendered from: the eye the head carries now, in
// LOCAL. Rendering from the pose relative to the reference and putting the result back where the
// reference stands is the eye carried by the head's own pose in LOCAL.
TEST(HeadTrackedPose, AnEyeRenderedForTheRelativePoseIsWhereTheHeadCarriesItInLocal) {
  const double s = std::sqrt(0.5);
  const HeadPose reference{{1.0, 1.6, -0.5}, {0.0, -s, 0.0, s}};
  const HeadPose now{{1.1, 1.55, -0.7}, {0.1, -0.9, 0.05, 0.4}};
  double norm = 0.0;
  for (const double component : now.orientation) norm += component * component;
  norm = std::sqrt(norm);
  HeadPose unit_now = now;
  for (double& component : unit_now.orientation) component /= norm;
  EyeView eye;
  eye.position_in_head = {0.0315, 0.0, 0.0};
  eye.field_of_view = field_of_view_from_deg(-49.0, 54.0, 54.0, -56.0);
  const EyeView in_local =
      eye_view_in_reference_space(eye, head_pose_relative_to(reference, unit_now), reference);
  const EyeView expected = eye_view_in_moved_head(eye, unit_now);
  for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(in_local.position_in_head[i], expected.position_in_head[i], 1e-12);
  for (size_t i = 0; i < 4; ++i)
    EXPECT_NEAR(in_local.orientation_in_head[i], expected.orientation_in_head[i], 1e-12);
  // Not the eye at the reference (the head did move).
  EXPECT_GT(std::abs(in_local.position_in_head[2] - eye_view_in_moved_head(eye, reference).position_in_head[2]), 0.05);
}

TEST(HeadTrackedPose, SanitizingRoundsToTheLogsStepAndHoldsTheLastPose) {
  const HeadPose raw{{0.12345678, -0.0000004, 0.5}, {0.0, -0.38268343236, 0.0, 0.92387953251}};
  const HeadPose used = sanitize_head_pose(raw, nullptr);
  EXPECT_EQ(used.position_m[0], std::round(0.12345678 / kHeadPoseStep) * kHeadPoseStep);
  EXPECT_EQ(used.position_m[1], 0.0);
  EXPECT_FALSE(std::signbit(used.position_m[1])) << "never -0";
  EXPECT_EQ(used.orientation[1], std::round(-0.38268343236 / kHeadPoseStep) * kHeadPoseStep);
  // What is logged reads back as it was used.
  std::string error;
  EXPECT_EQ(head_pose_of_entry(head_pose_entry(used), error), used);
  // No pose, or not one: the last one used holds; before any, the start's.
  EXPECT_EQ(sanitize_head_pose(std::nullopt, &used), used);
  EXPECT_EQ(sanitize_head_pose(HeadPose{{std::nan(""), 0.0, 0.0}, {0.0, 0.0, 0.0, 1.0}}, &used), used);
  EXPECT_EQ(sanitize_head_pose(HeadPose{{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 2.0}}, nullptr), HeadPose{});
  EXPECT_FALSE(head_pose_of_entry({0, 0, 0, 0, 0, 0, 0.5}, error));
  EXPECT_NE(error, "");
}

// Schema 12's head_pose: written only when set, read back as written, through the text too; a
// malformed entry is refused naming the field.
TEST(HeadTrackedPose, StimulusEventsCarryHeadPosesThroughTheLog) {
  StimulusEvent event;
  event.stamp = EventStamp{2.5, 9};
  event.trial = 1;
  event.stimulus = 0;
  event.present_s = {1.0, 1.011111};
  event.frame = {0, 0};
  event.hash = {"aa", "bb"};
  event.gaze = {{1.0, 2.0}, {1.0, 2.0}};
  event.right_eye_hash = std::vector<std::string>{"cc", "dd"};
  event.right_eye_gaze = std::vector<std::array<double, 2>>{{0.5, 2.0}, {0.5, 2.0}};
  EXPECT_FALSE(to_json(event).contains("head_pose")) << "a head-locked event writes none";
  event.head_pose = std::vector<std::array<double, 7>>{{0, 0, 0, 0, 0, 0, 1},
                                                       {0.000123, 0, -0.000001, 0, -0.001, 0, 0.9999995}};
  const nlohmann::json json = to_json(event);
  ASSERT_TRUE(json.contains("head_pose"));
  EXPECT_EQ(parse_stimulus(json), event);
  EXPECT_EQ(parse_stimulus(nlohmann::json::parse(json.dump())), event);
  nlohmann::json wrong = json;
  wrong["head_pose"][1] = {1, 2, 3};
  EXPECT_THROW(parse_stimulus(wrong), InputError);
}

}  // namespace
}  // namespace fovlab
