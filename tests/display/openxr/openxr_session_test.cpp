// A headset session on the test runtime (tests/xr_runtime), through the Khronos loader, with the
// OpenXR core validation layer and the Vulkan validation layer on: fovlab's Vulkan context is made
// through the runtime (XR_KHR_vulkan_enable2), the session reaches FOCUSED through the runtime's
// events, each eye's swapchain image as the runtime's compositor read it equals the offscreen
// frame it was given, byte for byte, and the session ends on xrRequestExitSession.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"
#include "display/openxr/openxr_eye_view.h"
#include "display/openxr/openxr_frame_loop.h"
#include "display/openxr/openxr_session.h"
#include "foveation/sampling_map.h"
#include "renderer/present/device_frame.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/buffer.h"
#include "tests/display/openxr/openxr_test_support.h"

namespace fovlab {
namespace {

using test::OpenXrTest;
using test::ScopedEnvironment;

using OpenXrHeadsetSession = OpenXrTest;

// The test runtime's read of the last projection layer (tests/xr_runtime/test_runtime.cpp).
using LastProjectionView = XrResult (*)(uint32_t, uint32_t*, uint32_t*, int64_t*, uint8_t*, uint64_t, int64_t*);

struct SubmittedView {
  XrResult result = XR_ERROR_RUNTIME_FAILURE;
  uint32_t width = 0;
  uint32_t height = 0;
  int64_t format = 0;
  std::vector<uint8_t> bytes;
  int64_t frames = 0;
};

SubmittedView last_submitted(LastProjectionView read, uint32_t view) {
  SubmittedView submitted;
  read(view, &submitted.width, &submitted.height, &submitted.format, nullptr, 0, &submitted.frames);
  submitted.bytes.resize(size_t{submitted.width} * submitted.height * 4);
  submitted.result = read(view, &submitted.width, &submitted.height, &submitted.format, submitted.bytes.data(),
                          submitted.bytes.size(), &submitted.frames);
  return submitted;
}

std::vector<std::string> names(const std::vector<XrSessionState>& states) {
  std::vector<std::string> named;
  for (const XrSessionState state : states) named.emplace_back(openxr_session_state_name(state));
  return named;
}

TEST_F(OpenXrHeadsetSession, ReachesFocusedShowsEachEyesFrameAndEndsOnRequest) {
  void* runtime_library = dlopen(FOVLAB_TEST_XR_RUNTIME_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(runtime_library, nullptr) << dlerror();
  const auto read_view =
      reinterpret_cast<LastProjectionView>(dlsym(runtime_library, "fovlab_test_xr_last_projection_view"));
  ASSERT_NE(read_view, nullptr);
  int64_t frames_before = 0;
  uint32_t unused_size = 0;
  int64_t unused_format = 0;
  read_view(0, &unused_size, &unused_size, &unused_format, nullptr, 0, &frames_before);
  {
    OpenXrSessionOptions options;
    options.eye_width_px = 64;
    options.eye_height_px = 72;
    options.validation = true;
    OpenXrSession session(options);
    ASSERT_TRUE(session.vulkan->validation_enabled());
    ASSERT_EQ(session.eyes[0].images.size(), 3u);

    // Each eye is given the offscreen renderer's GT frame of a built-in scene at the eye's size; the
    // eyes get different moments of the scene so that a swapped or repeated eye would show.
    SphereTracer tracer(*session.vulkan, load_scene("primitives"));
    SphereTraceSettings settings;
    settings.width = 64;
    settings.height = 72;
    settings.outputs = TraceOutputs::display;
    std::array<Rgba8Frame, 2> given;
    int frame_number = 0;
    const OpenXrEyeFrameSource eye_frame = [&](uint32_t eye, const OpenXrEyeView&) {
      settings.time_s = 0.5f * static_cast<float>(frame_number) + (eye == 0 ? 0.0f : 1.25f);
      settings.method = eye == 0 ? TraceMethod::ground_truth : TraceMethod::inverted_pyramid;
      const SphereTraceResult result = tracer.render(settings);
      given[eye] = read_back(result.display);
      return result.display;
    };

    std::vector<XrSessionState> seen = poll_openxr_events(session);
    ASSERT_TRUE(session.running) << "READY begins the session";
    int frames_to_focus = 0;
    int64_t layers_submitted = 0;
    while (session.state != XR_SESSION_STATE_FOCUSED && frames_to_focus < 10) {
      const OpenXrFrame frame = run_openxr_frame(session, eye_frame);
      EXPECT_EQ(frame.rendered, session.state == XR_SESSION_STATE_VISIBLE);
      layers_submitted += frame.rendered ? 1 : 0;
      const std::vector<XrSessionState> more = poll_openxr_events(session);
      seen.insert(seen.end(), more.begin(), more.end());
      ++frames_to_focus;
    }
    const std::vector<std::string> to_focus{"XR_SESSION_STATE_IDLE", "XR_SESSION_STATE_READY",
                                            "XR_SESSION_STATE_SYNCHRONIZED", "XR_SESSION_STATE_VISIBLE",
                                            "XR_SESSION_STATE_FOCUSED"};
    ASSERT_EQ(names(seen), to_focus);

    XrTime last_display_time = 0;
    for (int n = 0; n < 3; ++n) {
      frame_number = n + 1;
      const OpenXrFrame frame = run_openxr_frame(session, eye_frame);
      ASSERT_TRUE(frame.rendered);
      ++layers_submitted;
      EXPECT_FALSE(frame.discarded);
      EXPECT_EQ(frame.predicted_display_period, 11111111);  // 90 Hz
      if (last_display_time != 0) {
        EXPECT_GE(frame.predicted_display_time - last_display_time, 11111111);
        EXPECT_LE(frame.predicted_display_time - last_display_time, 11111112);
      }
      last_display_time = frame.predicted_display_time;
      // The eyes at -+IPD/2 along x, each field of view wider towards its temple.
      EXPECT_LT(frame.views[0].pose.position.x, 0.0f);
      EXPECT_NEAR(frame.views[1].pose.position.x - frame.views[0].pose.position.x, 0.063f, 1e-6f);
      EXPECT_GT(-frame.views[0].fov.angleLeft, frame.views[0].fov.angleRight);
      EXPECT_GT(frame.views[1].fov.angleRight, -frame.views[1].fov.angleLeft);
      EXPECT_NE(given[0].rgba, given[1].rgba) << "the two eyes must differ for the check to mean anything";
      for (uint32_t eye = 0; eye < 2; ++eye) {
        const SubmittedView submitted = last_submitted(read_view, eye);
        ASSERT_EQ(submitted.result, XR_SUCCESS);
        EXPECT_EQ(submitted.frames, frames_before + layers_submitted) << "one projection layer a rendered frame";
        EXPECT_EQ(submitted.width, 64u);
        EXPECT_EQ(submitted.height, 72u);
        EXPECT_EQ(submitted.format, VK_FORMAT_R8G8B8A8_SRGB);
        EXPECT_TRUE(submitted.bytes == given[eye].rgba) << "eye " << eye << " of frame " << n;
      }
    }

    // No valid pose (the runtime clears XrViewState's valid bits): no eye is asked for and the frame
    // ends with no layer; with the poses back, frames are rendered again.
    int eyes_asked = 0;
    const OpenXrEyeFrameSource counting_frame = [&](uint32_t eye, const OpenXrEyeView& view) {
      ++eyes_asked;
      return eye_frame(eye, view);
    };
    ::setenv("FOVLAB_TEST_XR_TRACKING", "lost", 1);
    const OpenXrFrame without_pose = run_openxr_frame(session, counting_frame);
    ::unsetenv("FOVLAB_TEST_XR_TRACKING");
    EXPECT_FALSE(without_pose.views_valid);
    EXPECT_FALSE(without_pose.rendered);
    EXPECT_EQ(eyes_asked, 0);
    EXPECT_EQ(last_submitted(read_view, 0).frames, frames_before + layers_submitted) << "no layer submitted";
    const OpenXrFrame with_pose = run_openxr_frame(session, counting_frame);
    EXPECT_TRUE(with_pose.views_valid);
    EXPECT_TRUE(with_pose.rendered);
    EXPECT_EQ(eyes_asked, 2);
    EXPECT_EQ(last_submitted(read_view, 0).frames, frames_before + layers_submitted + 1);

    // A world-fixed image (a head-tracked stimulus) goes to the compositor with the pose it was
    // rendered from; an image fixed to the view, with the pose located for the frame.
    using LastProjectionPose = XrResult (*)(uint32_t, float*);
    const auto read_pose =
        reinterpret_cast<LastProjectionPose>(dlsym(runtime_library, "fovlab_test_xr_last_projection_pose"));
    ASSERT_NE(read_pose, nullptr);
    const XrPosef rendered_from{{0.0f, -0.25f, 0.0f, 0.96824584f}, {0.2f, 1.5f, -0.3f}};
    const OpenXrFrame world_fixed = run_openxr_frame(session, eye_frame, {std::nullopt, rendered_from});
    ASSERT_TRUE(world_fixed.rendered);
    std::array<std::array<float, 7>, 2> submitted_poses{};
    for (uint32_t eye = 0; eye < 2; ++eye) ASSERT_EQ(read_pose(eye, submitted_poses[eye].data()), XR_SUCCESS);
    const XrPosef& located = world_fixed.views[0].pose;
    EXPECT_EQ(submitted_poses[0], (std::array<float, 7>{located.position.x, located.position.y, located.position.z,
                                                        located.orientation.x, located.orientation.y,
                                                        located.orientation.z, located.orientation.w}));
    EXPECT_EQ(submitted_poses[1], (std::array<float, 7>{0.2f, 1.5f, -0.3f, 0.0f, -0.25f, 0.0f, 0.96824584f}));

    request_openxr_exit(session);
    const std::vector<std::string> to_exit{"XR_SESSION_STATE_VISIBLE", "XR_SESSION_STATE_SYNCHRONIZED",
                                           "XR_SESSION_STATE_STOPPING", "XR_SESSION_STATE_IDLE",
                                           "XR_SESSION_STATE_EXITING"};
    EXPECT_EQ(names(poll_openxr_events(session)), to_exit);
    EXPECT_FALSE(session.running);
    EXPECT_TRUE(session.exiting);
    EXPECT_EQ(session.vulkan->validation_message_count(), 0u) << "Vulkan validation messages";
  }
  dlclose(runtime_library);
}

// Each eye rendered from the view the runtime located for it, relative to the head (the head-locked
// view model: eye_view_from_openxr), with its asymmetric angles: each eye's swapchain image, as the
// runtime's compositor read it, equals the renderer's offscreen frame of that eye's view, method and
// gaze byte for byte, for GT, IPR, FIPR and the sampling models (FIPR's fovea and the models' maps on
// the eye's off-axis image plane), with both
// validation layers silent. The test runtime's eyes sit at -+31.5 mm along x, the left one 54 degrees
// to the temple, 49 to the nose, 54 up and 56 down, the right one mirrored (docs/hmd.md).
TEST_F(OpenXrHeadsetSession, EachEyesImageIsTheOffscreenFrameOfItsView) {
  void* runtime_library = dlopen(FOVLAB_TEST_XR_RUNTIME_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(runtime_library, nullptr) << dlerror();
  const auto read_view =
      reinterpret_cast<LastProjectionView>(dlsym(runtime_library, "fovlab_test_xr_last_projection_view"));
  ASSERT_NE(read_view, nullptr);
  {
    OpenXrSessionOptions options;
    options.eye_width_px = 64;
    options.eye_height_px = 72;
    options.validation = true;
    OpenXrSession session(options);
    SphereTracer tracer(*session.vulkan, load_scene("primitives"));
    // The sampling models (Ye et al. 2022) too, their maps made on the eye's off-axis image plane.
    std::optional<SamplingModel> sampling_model;
    const auto eye_settings = [&sampling_model](TraceMethod method, const EyeView& view) {
      SphereTraceSettings settings;
      settings.method = method;
      settings.width = 64;
      settings.height = 72;
      settings.time_s = 2.0f;
      settings.outputs = TraceOutputs::display;
      settings.eye = view;
      if (method == TraceMethod::foveated_pyramid) {
        settings.foveation.display = eye_display(view, 64, 72);
        settings.foveation.gaze_x_px = 24.0;
        settings.foveation.gaze_y_px = 40.0;
        settings.foveation.acuity.fovea_radius_deg = 8.0;
      }
      if (method == TraceMethod::sampling_model) {
        SamplingSettings sampling;
        sampling.model = *sampling_model;
        sampling.inner_radius_deg = 8.0;
        sampling.outer_radius_deg = 20.0;
        sampling.outer_pixel_size_px = 4.0;
        settings.sampling = make_sampling_map(sampling, eye_display(view, 64, 72), 24.0, 40.0);
      }
      return settings;
    };
    TraceMethod method = TraceMethod::ground_truth;
    std::array<EyeView, 2> rendered_views;
    const OpenXrEyeFrameSource eye_frame = [&](uint32_t eye, const OpenXrEyeView& view) {
      rendered_views[eye] = eye_view_from_openxr(view.in_head);
      return tracer.render(eye_settings(method, rendered_views[eye])).display;
    };
    poll_openxr_events(session);
    for (int frames = 0; session.state != XR_SESSION_STATE_FOCUSED && frames < 10; ++frames) {
      run_openxr_frame(session, eye_frame);
      poll_openxr_events(session);
    }
    ASSERT_EQ(session.state, XR_SESSION_STATE_FOCUSED);

    const double degree = std::acos(-1.0) / 180.0;
    const std::vector<std::pair<TraceMethod, std::optional<SamplingModel>>> cases = {
        {TraceMethod::ground_truth, std::nullopt},
        {TraceMethod::inverted_pyramid, std::nullopt},
        {TraceMethod::foveated_pyramid, std::nullopt},
        {TraceMethod::sampling_model, SamplingModel::rectangular},
        {TraceMethod::sampling_model, SamplingModel::hyperbolic},
        {TraceMethod::sampling_model, SamplingModel::linear},
        {TraceMethod::sampling_model, SamplingModel::kernel_log_polar}};
    for (const auto& [frame_method, frame_model] : cases) {
      method = frame_method;
      sampling_model = frame_model;
      const std::string name = frame_model ? sampling_model_name(*frame_model) : method_name(method);
      const OpenXrFrame frame = run_openxr_frame(session, eye_frame);
      ASSERT_TRUE(frame.rendered);
      std::array<std::vector<uint8_t>, 2> submitted_bytes;
      for (uint32_t eye = 0; eye < 2; ++eye) {
        const std::string where = name + " eye " + std::to_string(eye);
        // The view the eye was rendered from is the runtime's: the eye in the head, its four angles.
        const EyeView& view = rendered_views[eye];
        EXPECT_NEAR(view.position_in_head[0], eye == 0 ? -0.0315 : 0.0315, 1e-6) << where;
        EXPECT_EQ(view.position_in_head[1], 0.0) << where;
        EXPECT_EQ(view.orientation_in_head[3], 1.0) << where;
        EXPECT_NEAR(view.field_of_view.angle_left_rad, (eye == 0 ? -54.0 : -49.0) * degree, 1e-6) << where;
        EXPECT_NEAR(view.field_of_view.angle_right_rad, (eye == 0 ? 49.0 : 54.0) * degree, 1e-6) << where;
        EXPECT_NEAR(view.field_of_view.angle_up_rad, 54.0 * degree, 1e-6) << where;
        EXPECT_NEAR(view.field_of_view.angle_down_rad, -56.0 * degree, 1e-6) << where;
        EXPECT_EQ(frame.views_in_head[eye].pose.position.x, frame.views[eye].pose.position.x)
            << "the head does not move";

        const SubmittedView submitted = last_submitted(read_view, eye);
        ASSERT_EQ(submitted.result, XR_SUCCESS) << where;
        const Rgba8Frame offscreen = read_back(tracer.render(eye_settings(method, view)).display);
        EXPECT_TRUE(submitted.bytes == offscreen.rgba) << where;
        submitted_bytes[eye] = submitted.bytes;
        // The eye's own view matters: the scene camera's symmetric frame of the same size differs.
        SphereTraceSettings desktop = eye_settings(method, view);
        desktop.eye.reset();
        if (method == TraceMethod::foveated_pyramid)
          desktop.foveation.display = display_from_size(64, 72, 64.0, 72.0, 100.0);
        EXPECT_FALSE(read_back(tracer.render(desktop).display).rgba == offscreen.rgba) << where;
      }
      EXPECT_NE(submitted_bytes[0], submitted_bytes[1]) << name << ": the eyes see different views";
    }
    request_openxr_exit(session);
    poll_openxr_events(session);
    EXPECT_EQ(session.vulkan->validation_message_count(), 0u) << "Vulkan validation messages";
  }
  dlclose(runtime_library);
}

// A view in the head's frame becomes the eye view as it is: the position scaled to scene units, the
// orientation and the four angles unchanged.
TEST(OpenXrEyeView, PoseAndAnglesBecomeTheEyeView) {
  XrView view{XR_TYPE_VIEW};
  view.pose.position = {-0.032f, 0.01f, -0.005f};
  view.pose.orientation = {0.0f, 0.0871557f, 0.0f, 0.9961947f};  // 10 degrees about y
  view.fov = {-0.9f, 0.8f, 0.85f, -0.95f};
  const EyeView eye = eye_view_from_openxr(view, 100.0);
  EXPECT_FLOAT_EQ(float(eye.position_in_head[0]), -3.2f);
  EXPECT_FLOAT_EQ(float(eye.position_in_head[1]), 1.0f);
  EXPECT_FLOAT_EQ(float(eye.position_in_head[2]), -0.5f);
  EXPECT_EQ(eye.orientation_in_head[1], double(0.0871557f));
  EXPECT_EQ(eye.orientation_in_head[3], double(0.9961947f));
  EXPECT_EQ(eye.field_of_view.angle_left_rad, double(-0.9f));
  EXPECT_EQ(eye.field_of_view.angle_right_rad, double(0.8f));
  EXPECT_EQ(eye.field_of_view.angle_up_rad, double(0.85f));
  EXPECT_EQ(eye.field_of_view.angle_down_rad, double(-0.95f));
}

// The frame loop's order, as the specification gives it, asked of the runtime through the loader
// and the validation layer: a frame must be waited for before it begins, begun before it ends; an
// image acquired before it is waited for, waited for before it is released; a session ends only
// when it is stopping.
TEST_F(OpenXrHeadsetSession, CallsOutOfOrderAreRefused) {
  OpenXrSessionOptions options;
  options.eye_width_px = 16;
  options.eye_height_px = 16;
  options.validation = true;
  OpenXrSession session(options);
  XrFrameState frame_state{XR_TYPE_FRAME_STATE};
  EXPECT_EQ(xrWaitFrame(session.session, nullptr, &frame_state), XR_ERROR_SESSION_NOT_RUNNING);
  poll_openxr_events(session);  // IDLE, READY: begun
  ASSERT_TRUE(session.running);
  EXPECT_EQ(xrBeginFrame(session.session, nullptr), XR_ERROR_CALL_ORDER_INVALID);
  XrFrameEndInfo end_info{XR_TYPE_FRAME_END_INFO};
  end_info.displayTime = 1;
  end_info.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  EXPECT_EQ(xrEndFrame(session.session, &end_info), XR_ERROR_CALL_ORDER_INVALID);
  XrSwapchainImageWaitInfo wait{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
  wait.timeout = XR_INFINITE_DURATION;
  const XrSwapchain swapchain = session.eyes[0].handle;
  EXPECT_EQ(xrWaitSwapchainImage(swapchain, &wait), XR_ERROR_CALL_ORDER_INVALID);
  EXPECT_EQ(xrReleaseSwapchainImage(swapchain, nullptr), XR_ERROR_CALL_ORDER_INVALID);
  uint32_t index = 99;
  ASSERT_EQ(xrAcquireSwapchainImage(swapchain, nullptr, &index), XR_SUCCESS);
  EXPECT_EQ(index, 0u);
  EXPECT_EQ(xrReleaseSwapchainImage(swapchain, nullptr), XR_ERROR_CALL_ORDER_INVALID);  // not waited for
  ASSERT_EQ(xrWaitSwapchainImage(swapchain, &wait), XR_SUCCESS);
  ASSERT_EQ(xrReleaseSwapchainImage(swapchain, nullptr), XR_SUCCESS);
  EXPECT_EQ(xrEndSession(session.session), XR_ERROR_SESSION_NOT_STOPPING);
  // A frame begun twice: the first is discarded.
  ASSERT_EQ(xrWaitFrame(session.session, nullptr, &frame_state), XR_SUCCESS);
  ASSERT_EQ(xrBeginFrame(session.session, nullptr), XR_SUCCESS);
  ASSERT_EQ(xrWaitFrame(session.session, nullptr, &frame_state), XR_SUCCESS);
  EXPECT_EQ(xrBeginFrame(session.session, nullptr), XR_FRAME_DISCARDED);
  end_info.displayTime = frame_state.predictedDisplayTime;
  EXPECT_EQ(xrEndFrame(session.session, &end_info), XR_SUCCESS);
  EXPECT_EQ(session.vulkan->validation_message_count(), 0u);
}

// The runtime's own stop (STOPPING without EXITING: FOVLAB_TEST_XR_STOP_AT_FRAME with
// FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS): poll_openxr_events ends the session at once and it is
// IDLE; the frame loop, a second xrEndSession, an exit request and an early xrBeginSession are then
// refused as the specification says; the runtime offers READY after its polls, poll_openxr_events
// begins the session again, and the same swapchains take it back to FOCUSED, a layer submitted.
TEST_F(OpenXrHeadsetSession, TheRuntimesOwnStopEndsTheSessionAndReadyAgainBeginsIt) {
  const ScopedEnvironment stop_at{"FOVLAB_TEST_XR_STOP_AT_FRAME", "5"};
  const ScopedEnvironment ready_again{"FOVLAB_TEST_XR_READY_AGAIN_AFTER_POLLS", "3"};
  OpenXrSessionOptions options;
  options.eye_width_px = 16;
  options.eye_height_px = 16;
  options.validation = true;
  OpenXrSession session(options);
  vk::Buffer grey(*session.vulkan, VkDeviceSize{16} * 16 * 4, vk::MemoryUse::host_upload);
  auto* pixels = static_cast<uint32_t*>(grey.mapped());
  std::fill(pixels, pixels + 16 * 16, 0xff808080u);
  grey.flush();
  const OpenXrEyeFrameSource eye_frame = [&](uint32_t, const OpenXrEyeView&) {
    return DeviceRgba8Frame{session.vulkan.get(), grey.handle(), 16, 16};
  };

  poll_openxr_events(session);  // IDLE, READY: begun
  ASSERT_TRUE(session.running);
  std::vector<XrSessionState> seen;
  for (int frame = 1; frame <= 5; ++frame) {
    ASSERT_TRUE(session.running) << "stopped before frame " << frame;
    run_openxr_frame(session, eye_frame);
    const std::vector<XrSessionState> more = poll_openxr_events(session);
    seen.insert(seen.end(), more.begin(), more.end());
  }
  const std::vector<std::string> to_stop{"XR_SESSION_STATE_SYNCHRONIZED", "XR_SESSION_STATE_VISIBLE",
                                         "XR_SESSION_STATE_FOCUSED",      "XR_SESSION_STATE_VISIBLE",
                                         "XR_SESSION_STATE_SYNCHRONIZED", "XR_SESSION_STATE_STOPPING",
                                         "XR_SESSION_STATE_IDLE"};
  ASSERT_EQ(names(seen), to_stop);
  EXPECT_FALSE(session.running) << "STOPPING ends the session";
  EXPECT_FALSE(session.exiting) << "a stop is not the end";

  XrFrameState frame_state{XR_TYPE_FRAME_STATE};
  EXPECT_EQ(xrWaitFrame(session.session, nullptr, &frame_state), XR_ERROR_SESSION_NOT_RUNNING);
  EXPECT_EQ(xrBeginFrame(session.session, nullptr), XR_ERROR_SESSION_NOT_RUNNING);
  EXPECT_EQ(xrEndSession(session.session), XR_ERROR_SESSION_NOT_RUNNING);
  EXPECT_EQ(xrRequestExitSession(session.session), XR_ERROR_SESSION_NOT_RUNNING);
  XrSessionBeginInfo begin{XR_TYPE_SESSION_BEGIN_INFO};
  begin.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
  EXPECT_EQ(xrBeginSession(session.session, &begin), XR_ERROR_SESSION_NOT_READY);

  // The poll that handed out IDLE found nothing after it (1); two more polls find nothing (2, 3:
  // READY queued), and the next hands READY out, which begins the session.
  std::vector<XrSessionState> again;
  int polls = 0;
  while (!session.running && polls < 10) {
    const std::vector<XrSessionState> more = poll_openxr_events(session);
    again.insert(again.end(), more.begin(), more.end());
    ++polls;
  }
  EXPECT_EQ(polls, 3);
  ASSERT_EQ(names(again), std::vector<std::string>{"XR_SESSION_STATE_READY"});
  ASSERT_TRUE(session.running);
  EXPECT_EQ(xrBeginSession(session.session, &begin), XR_ERROR_SESSION_RUNNING);

  std::vector<XrSessionState> to_focus;
  for (int frame = 0; frame < 5 && session.state != XR_SESSION_STATE_FOCUSED; ++frame) {
    run_openxr_frame(session, eye_frame);
    const std::vector<XrSessionState> more = poll_openxr_events(session);
    to_focus.insert(to_focus.end(), more.begin(), more.end());
  }
  EXPECT_EQ(names(to_focus), (std::vector<std::string>{"XR_SESSION_STATE_SYNCHRONIZED", "XR_SESSION_STATE_VISIBLE",
                                                       "XR_SESSION_STATE_FOCUSED"}));
  EXPECT_TRUE(run_openxr_frame(session, eye_frame).rendered) << "the kept swapchains show the eyes again";

  request_openxr_exit(session);
  for (int frame = 0; frame < 5 && session.running; ++frame) {
    run_openxr_frame(session, eye_frame);
    poll_openxr_events(session);
  }
  EXPECT_FALSE(session.running);
  EXPECT_TRUE(session.exiting) << "an exit the application asked for ends in EXITING";
  EXPECT_EQ(session.vulkan->validation_message_count(), 0u);
}

// In a child process: the 1.0.20 loader keeps the extension list of the runtime as it first loaded
// it, so a runtime without the extension would stay without it for the rest of the process.
TEST_F(OpenXrHeadsetSession, RuntimeWithoutVulkanEnable2IsRefusedInOneLine) {
  const auto refuse = [] {
    setenv("FOVLAB_TEST_XR_VULKAN", "absent", 1);
    try {
      OpenXrSession session(OpenXrSessionOptions{16, 16, true});
    } catch (const InputError& error) {
      const std::string message = error.what();
      std::fprintf(stderr, "refused: %s\n", message.c_str());
      std::fflush(stderr);
      std::_Exit(message.find('\n') == std::string::npos ? 2 : 3);
    }
    std::_Exit(0);
  };
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process: the test binary run again
  EXPECT_EXIT(refuse(), ::testing::ExitedWithCode(2),
              "refused: openxr: the OpenXR runtime does not offer XR_KHR_vulkan_enable2; fovlab renders through "
              "Vulkan, so it cannot run a headset session on this runtime");
}

TEST_F(OpenXrHeadsetSession, EyeImageOverTheRuntimesMaximumIsRefused) {
  try {
    OpenXrSession session(OpenXrSessionOptions{2881, 16, true});
    FAIL() << "an eye image wider than the runtime's maximum";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "openxr: eye image 2881x16: expected at most the runtime's 2880x3200");
  }
}

}  // namespace
}  // namespace fovlab
