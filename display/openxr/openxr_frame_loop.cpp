#include "display/openxr/openxr_frame_loop.h"

#include <stdexcept>
#include <string>

#include "renderer/vk/submission.h"

namespace fovlab {
namespace {

void check_frame_call(XrResult result, const char* call) {
  if (XR_FAILED(result)) throw std::runtime_error(std::string("openxr: ") + call + ": " + openxr_result_name(result));
}

// The frame's bytes into the swapchain image, which XR_KHR_vulkan_enable2 hands over and takes back
// in VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: to a transfer destination, one buffer-to-image copy,
// and back. The frame's RGBA8 bytes land as they are in the R8G8B8A8_SRGB image.
void copy_into(const vk::Context& context, const DeviceRgba8Frame& frame, VkImage image) {
  vk::OneTimeCommands commands(context);
  // The renderer's writes of the frame (compute or transfer) before the copy reads it.
  vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_READ_BIT);
  vk::image_layout_barrier(commands.handle(), image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                           VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
  VkBufferImageCopy region{};
  region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  region.imageExtent = {static_cast<uint32_t>(frame.width), static_cast<uint32_t>(frame.height), 1};
  vkCmdCopyBufferToImage(commands.handle(), frame.buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
  // Back for the runtime; the wait for the submission below orders its later use.
  vk::image_layout_barrier(commands.handle(), image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0);
  commands.submit_and_wait();
}

}  // namespace

OpenXrFrame run_openxr_frame(OpenXrSession& session, const OpenXrEyeFrameSource& eye_frame,
                             const std::array<std::optional<XrPosef>, 2>& rendered_from) {
  XrFrameState frame_state{XR_TYPE_FRAME_STATE};
  check_frame_call(xrWaitFrame(session.session, nullptr, &frame_state), "xrWaitFrame");
  OpenXrFrame frame;
  frame.predicted_display_time = frame_state.predictedDisplayTime;
  frame.predicted_display_period = frame_state.predictedDisplayPeriod;
  const XrResult begun = xrBeginFrame(session.session, nullptr);
  check_frame_call(begun, "xrBeginFrame");
  frame.discarded = begun == XR_FRAME_DISCARDED;

  XrFrameEndInfo end_info{XR_TYPE_FRAME_END_INFO};
  end_info.displayTime = frame_state.predictedDisplayTime;
  end_info.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
  std::array<XrCompositionLayerProjectionView, 2> projection_views{};
  XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
  const XrCompositionLayerBaseHeader* layers[] = {reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer)};
  if (frame_state.shouldRender) {
    XrViewLocateInfo locate{XR_TYPE_VIEW_LOCATE_INFO};
    locate.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    locate.displayTime = frame_state.predictedDisplayTime;
    // Whether the runtime vouches for the views' poses (both valid bits; a pose need not be tracked:
    // a runtime may infer one while tracking is lost, and says so by the tracked bits alone).
    const auto locate_in = [&](XrSpace space, std::array<XrView, 2>& views) {
      locate.space = space;
      XrViewState view_state{XR_TYPE_VIEW_STATE};
      views.fill(XrView{XR_TYPE_VIEW});
      uint32_t view_count = 0;
      check_frame_call(xrLocateViews(session.session, &locate, &view_state, 2, &view_count, views.data()),
                       "xrLocateViews");
      if (view_count != 2)
        throw std::runtime_error("openxr: xrLocateViews gave " + std::to_string(view_count) + " views");
      constexpr XrViewStateFlags valid = XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT;
      return (view_state.viewStateFlags & valid) == valid;
    };
    const bool valid_in_local = locate_in(session.local_space, frame.views);
    const bool valid_in_head = locate_in(session.view_space, frame.views_in_head);
    frame.views_valid = valid_in_local && valid_in_head;
  }
  // Without valid poses (the runtime has none to give: before tracking starts, or once it has lost
  // every reference) there is no view to render for: the frame ends with no layer, as one the runtime
  // said not to render.
  if (frame_state.shouldRender && frame.views_valid) {
    for (uint32_t eye = 0; eye < 2; ++eye) {
      const DeviceRgba8Frame image = eye_frame(eye, OpenXrEyeView{frame.views[eye], frame.views_in_head[eye]});
      if (!image || image.context != session.vulkan.get() || image.width != static_cast<int>(session.eye_width_px) ||
          image.height != static_cast<int>(session.eye_height_px))
        throw std::invalid_argument("openxr: eye " + std::to_string(eye) + "'s frame is " +
                                    std::to_string(image.width) + "x" + std::to_string(image.height) +
                                    " on its device; expected " + std::to_string(session.eye_width_px) + "x" +
                                    std::to_string(session.eye_height_px) + " on the session's");
      const OpenXrEyeSwapchain& swapchain = session.eyes[eye];
      uint32_t index = 0;
      check_frame_call(xrAcquireSwapchainImage(swapchain.handle, nullptr, &index), "xrAcquireSwapchainImage");
      XrSwapchainImageWaitInfo wait{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
      wait.timeout = XR_INFINITE_DURATION;
      check_frame_call(xrWaitSwapchainImage(swapchain.handle, &wait), "xrWaitSwapchainImage");
      copy_into(*session.vulkan, image, swapchain.images.at(index));
      check_frame_call(xrReleaseSwapchainImage(swapchain.handle, nullptr), "xrReleaseSwapchainImage");
      frame.image_index[eye] = index;

      XrCompositionLayerProjectionView& view = projection_views[eye];
      view = XrCompositionLayerProjectionView{XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
      view.pose = rendered_from[eye] ? *rendered_from[eye] : frame.views[eye].pose;
      view.fov = frame.views[eye].fov;
      view.subImage.swapchain = swapchain.handle;
      view.subImage.imageRect.extent = {static_cast<int32_t>(session.eye_width_px),
                                        static_cast<int32_t>(session.eye_height_px)};
    }
    layer.space = session.local_space;
    layer.viewCount = 2;
    layer.views = projection_views.data();
    end_info.layerCount = 1;
    end_info.layers = layers;
    frame.rendered = true;
  }
  // Late: handed to the compositor after the time it was to be displayed (measured last, so that
  // everything this frame did counts).
  frame.end_frame_time = openxr_time_now(session);
  frame.late = frame.end_frame_time && *frame.end_frame_time > frame.predicted_display_time;
  check_frame_call(xrEndFrame(session.session, &end_info), "xrEndFrame");
  return frame;
}

std::optional<XrPosef> locate_head_in_local(const OpenXrSession& session, XrTime time) {
  XrSpaceLocation location{XR_TYPE_SPACE_LOCATION};
  check_frame_call(xrLocateSpace(session.view_space, session.local_space, time, &location), "xrLocateSpace");
  constexpr XrSpaceLocationFlags valid = XR_SPACE_LOCATION_ORIENTATION_VALID_BIT | XR_SPACE_LOCATION_POSITION_VALID_BIT;
  if ((location.locationFlags & valid) != valid) return std::nullopt;
  return location.pose;
}

}  // namespace fovlab
