// A stimulus library for a headset eye (protocols/stimuli/stimulus_library.h, issue 42): its frames
// are exactly the renderer's own per-eye frames for that view and gaze (computed here through the
// renderers directly, the eye put in by hand), not the desktop's, and not the other eye's; the eye's
// off-axis display reaches every conversion that takes a display; the families that cannot render
// an eye's view are refused by prepare with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "core/input_error.h"
#include "foveation/voronoi_reconstruction.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/prerender/path_scene_source.h"
#include "renderer/scene/eye_view.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/volume/volume_raycaster.h"
#include "renderer/volume/volume_scene.h"
#include "tests/renderer/vulkan_test_fixture.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

constexpr int kWidthPx = 48, kHeightPx = 40;

// A headset's eyes, 63 mm apart (a scene unit a metre), with mirrored asymmetric fields of view.
EyeView eye_of(int side) {
  EyeView eye;
  eye.position_in_head = {side == 0 ? -0.0315 : 0.0315, 0.0, 0.0};
  eye.field_of_view = side == 0 ? field_of_view_from_deg(-30.0, 22.0, 24.0, -27.0)
                                : field_of_view_from_deg(-22.0, 30.0, 24.0, -27.0);
  return eye;
}

// A spec at the test's size; foveated ones carry the flat stand-in display a headset study is planned
// on (which an eye's library ignores).
StimulusSpec spec_of(RenderMethod method, const std::string& scene) {
  StimulusSpec spec;
  spec.scene = scene;
  spec.parameters = default_parameters(method);
  spec.width_px = kWidthPx;
  spec.height_px = kHeightPx;
  spec.frame_count = 1;
  spec.camera_start_s = 1.5;
  if (StimulusDisplay* display = display_of(spec.parameters)) *display = StimulusDisplay{300.0, 250.0, 400.0};
  return spec;
}

StimulusImage image_at(double gaze_x_px, double gaze_y_px) {
  StimulusImage image;
  image.gaze.x_px = gaze_x_px;
  image.gaze.y_px = gaze_y_px;
  return image;
}

// The sphere tracer's own frame of the spec for the eye: the desktop conversion, then the eye put in
// as the tracer takes it (its view, and FIPR's display for eccentricity the eye's image plane).
std::vector<uint8_t> sphere_traced_for_eye(vk::Context& context, const StimulusSpec& spec, const EyeView& eye,
                                           const StimulusImage& image) {
  SphereTracer tracer(context, load_scene(spec.scene));
  SphereTraceSettings settings = sphere_trace_settings(spec, image.frame);
  settings.eye = eye;
  settings.outputs = TraceOutputs::display;
  if (describe(spec.method()).depends_on_gaze) {
    settings.foveation.display = eye_display(eye, spec.width_px, spec.height_px);
    settings.foveation.gaze_x_px = image.gaze.x_px;
    settings.foveation.gaze_y_px = image.gaze.y_px;
    settings.foveation.frame_index = uint32_t(image.image_index);
    // rmfr's map is in pixels alone: the same on any display.
    if (settings.sampling) settings.sampling = sampling_map(spec, image.gaze.x_px, image.gaze.y_px);
  }
  return read_back(tracer.render(settings).display).rgba;
}

// The volume raycaster's own frame for the eye; fvolume's mask made on the eye's image plane.
std::vector<uint8_t> volume_for_eye(vk::Context& context, const StimulusSpec& spec, const EyeView& eye,
                                    const StimulusImage& image) {
  const VolumeScene scene = load_volume_scene(spec.scene);
  const VolumeGrid grid = load_scene_volume(scene, volume_limits(context));
  VolumeRaycaster raycaster(context, scene, grid);
  VolumeRenderSettings settings = volume_render_settings(spec, image.frame);
  settings.eye = eye;
  const auto* foveated = std::get_if<FoveatedVolumeRaycastParameters>(&spec.parameters);
  if (!foveated) {
    settings.frame_index = uint32_t(image.frame);
    return read_back(raycaster.display_full_on_device(settings)).rgba;
  }
  VoronoiMaskSettings mask = voronoi_mask_settings(spec.width_px, spec.height_px,
                                                   eye_display(eye, spec.width_px, spec.height_px),
                                                   foveated->density_sigma_deg);
  mask.seed = foveated->mask_seed;
  raycaster.set_reconstruction(make_voronoi_reconstruction(mask));
  settings.frame_index = uint32_t(image.image_index);
  return read_back(raycaster.display_foveated_on_device(settings, image.gaze.x_px, image.gaze.y_px,
                                                        foveated->temporal_smoothing))
      .rgba;
}

// FIPR whose traced pixels follow the eccentricity alone (at this size nearly every pixel is near an
// edge, which the default combination traces in full): a small fovea and an outer periphery (nothing
// traced beyond it), whose edge falls on other pixels on the eye's display and on the stand-in's
// (about 1.2 and 0.9 degrees a pixel).
void small_fovea(FoveatedPyramidParameters& fipr) {
  fipr.combine = MaskCombine::acuity;
  fipr.fovea_radius_deg = 3.0;
  fipr.outer_periphery_radius_deg = 12.0;
}

class EyeStimulusLibrary : public test::VulkanTest {
 protected:
  // Each eye's library's frame equals the renderer's for that eye, and differs from the desktop's
  // and from the other eye's.
  template <class Expected>
  void expect_eye_frames(const StimulusSpec& spec, const StimulusImage& image, Expected expected) {
    StimulusLibrary desktop(context());
    const std::vector<uint8_t> desktop_bytes = desktop.render(spec, image).image.rgba;
    std::vector<uint8_t> eye_bytes[2];
    for (int side = 0; side < 2; ++side) {
      StimulusLibrary library(context(), "stimuli/cache", eye_of(side));
      ASSERT_EQ(library.eye(), eye_of(side));
      const PreparedFrame frame = library.render(spec, image);
      eye_bytes[side] = frame.image.rgba;
      ASSERT_EQ(eye_bytes[side].size(), size_t(kWidthPx * kHeightPx * 4)) << spec.method_name();
      EXPECT_EQ(frame.hash, frame_hash(frame.image));
      EXPECT_TRUE(eye_bytes[side] == expected(context(), spec, eye_of(side), image))
          << spec.method_name() << ", eye " << side << ": not the renderer's own frame for the eye";
      EXPECT_NE(eye_bytes[side], desktop_bytes) << spec.method_name() << ", eye " << side;
    }
    EXPECT_NE(eye_bytes[0], eye_bytes[1]) << spec.method_name() << ": both eyes alike";
  }
};

TEST_F(EyeStimulusLibrary, SphereTracedFramesAreTheTracersOwnForTheEye) {
  for (RenderMethod method : {RenderMethod::ground_truth, RenderMethod::inverted_pyramid})
    expect_eye_frames(spec_of(method, "primitives"), StimulusImage{}, sphere_traced_for_eye);
  // Gaze-dependent: at a gaze off the centre, where the eye's off-axis display and the stand-in's
  // eccentricities differ.
  for (RenderMethod method : {RenderMethod::foveated_pyramid, sampled_method(0, SamplingModel::rectangular)}) {
    StimulusSpec spec = spec_of(method, "primitives");
    if (auto* fipr = std::get_if<FoveatedPyramidParameters>(&spec.parameters)) small_fovea(*fipr);
    expect_eye_frames(spec, image_at(9.5, 31.25), sphere_traced_for_eye);
  }
}

// FIPR on the eye's display, not on the stand-in's: the tracer given the stand-in's display with the
// eye's view makes another frame (so the check above can fail on the display alone).
TEST_F(EyeStimulusLibrary, FiprTakesTheEyesDisplayNotTheStandIns) {
  StimulusSpec spec = spec_of(RenderMethod::foveated_pyramid, "primitives");
  small_fovea(std::get<FoveatedPyramidParameters>(spec.parameters));
  const StimulusImage image = image_at(24.0, 20.0);
  StimulusLibrary library(context(), "stimuli/cache", eye_of(0));
  SphereTracer tracer(context(), load_scene(spec.scene));
  SphereTraceSettings stand_in = sphere_trace_settings(spec, 0);  // the stand-in's display
  stand_in.eye = eye_of(0);
  stand_in.outputs = TraceOutputs::display;
  stand_in.foveation.gaze_x_px = image.gaze.x_px;
  stand_in.foveation.gaze_y_px = image.gaze.y_px;
  EXPECT_NE(library.render(spec, image).image.rgba, read_back(tracer.render(stand_in).display).rgba);
}

TEST_F(EyeStimulusLibrary, VolumeFramesAreTheRaycastersOwnForTheEye) {
  expect_eye_frames(spec_of(RenderMethod::volume_raycast, "marschner-lobb"), StimulusImage{}, volume_for_eye);
  expect_eye_frames(spec_of(RenderMethod::foveated_volume_raycast, "marschner-lobb"), image_at(30.5, 12.0),
                    volume_for_eye);
}

// Prepared (gaze-independent) frames are the library's own: each eye's library holds its eye's.
TEST_F(EyeStimulusLibrary, PreparedFramesAreEachEyesOwn) {
  const StimulusSpec gt = spec_of(RenderMethod::ground_truth, "primitives");
  StimulusLibrary left(context(), "stimuli/cache", eye_of(0)), right(context(), "stimuli/cache", eye_of(1));
  left.prepare({{7, gt}});
  right.prepare({{7, gt}});
  const Rgba8Frame& left_frame = left.frame(7, gt, StimulusImage{}).image;
  const Rgba8Frame& right_frame = right.frame(7, gt, StimulusImage{}).image;
  EXPECT_TRUE(left_frame.rgba == sphere_traced_for_eye(context(), gt, eye_of(0), StimulusImage{}));
  EXPECT_TRUE(right_frame.rgba == sphere_traced_for_eye(context(), gt, eye_of(1), StimulusImage{}));
  EXPECT_NE(left_frame.rgba, right_frame.rgba);
}

TEST_F(EyeStimulusLibrary, ImageStimuliAreRefusedByPrepareInOneLine) {
  StimulusLibrary library(context(), "stimuli/cache", eye_of(0));
  const auto refusal = [&](const StimulusSpec& spec) -> std::string {
    try {
      library.prepare({{0, spec_of(RenderMethod::ground_truth, "primitives")}, {1, spec}});
    } catch (const InputError& error) {
      return error.what();
    }
    return "";
  };
  const StimulusSpec images = spec_of(sampled_method(2, SamplingModel::rectangular), "stimuli/no-such-folder");
  const std::string image_refusal = refusal(images);
  EXPECT_EQ(image_refusal.rfind(std::string(images.method_name()) + ": a headset study cannot show it yet: per-eye "
                                                                     "images are not made",
                                0),
            0u)
      << image_refusal;
  EXPECT_EQ(image_refusal.find('\n'), std::string::npos);
  // The methods it does show, from the families: the path-traced ones among them.
  for (const char* shown : {"it shows gt, ipr, fipr, ", " pt,", " fpt,", " volume, fvolume"})
    EXPECT_NE(image_refusal.find(shown), std::string::npos) << image_refusal;
  EXPECT_EQ(image_refusal.find(" img-rmfr"), std::string::npos) << image_refusal;
  // Refused before anything was rendered (the gt stimulus listed first included).
  EXPECT_EQ(library.render_seconds(), 0.0);
  // render() refuses them too (a replay renders without prepare).
  EXPECT_THROW(library.render(images, StimulusImage{}), InputError);
}

// Pre-rendered path-traced frames are made per eye: each eye's sequence (its key names the eye's
// view) has a folder of its own in the cache, holding the path tracer's frames of that eye's view,
// and each eye's library shows its own.
TEST_F(EyeStimulusLibrary, PathTracedFramesArePreRenderedPerEye) {
  testing::TempDir cache{"eye-prerender"};
  StimulusSpec pt = spec_of(RenderMethod::path_traced, "courtyard");
  std::get<PathTracedParameters>(pt.parameters).samples_per_pixel = 2;
  std::get<PathTracedParameters>(pt.parameters).max_bounces = 2;
  const PathTraceSequence desktop = path_traced_frames(pt).sequences.at(0);
  const PathTraceSequence left_sequence = path_traced_frames(pt, eye_of(0)).sequences.at(0);
  const PathTraceSequence right_sequence = path_traced_frames(pt, eye_of(1)).sequences.at(0);
  EXPECT_EQ(desktop.description().find(";eye="), std::string::npos) << "the desktop's keys are unchanged";
  EXPECT_NE(left_sequence.description().find(";eye=position:"), std::string::npos) << left_sequence.description();
  EXPECT_NE(left_sequence.description(), right_sequence.description());
  ASSERT_TRUE(left_sequence.settings(0).eye.has_value());
  EXPECT_EQ(*left_sequence.settings(0).eye, eye_of(0));

  StimulusLibrary left(context(), cache.path(), eye_of(0)), right(context(), cache.path(), eye_of(1));
  left.prepare({{0, pt}});
  right.prepare({{0, pt}});
  const Rgba8Frame left_frame = left.frame(0, pt, StimulusImage{}).image;
  const Rgba8Frame right_frame = right.frame(0, pt, StimulusImage{}).image;
  EXPECT_NE(left_frame.rgba, right_frame.rgba);
  // Each eye's cached frame is the path tracer's own render of that eye's view.
  FrameCache frames(context(), cache.path());
  PathTracer tracer(context(), load_path_scene("courtyard").scene);
  const Image rendered = tracer.render(left_sequence.settings(0)).image;
  const Image cached = frames.frame(left_sequence, 0);
  ASSERT_EQ(cached.width, rendered.width);
  EXPECT_TRUE(cached.pixels == rendered.pixels);
  EXPECT_NE(frames.folder(left_sequence), frames.folder(right_sequence));
  // The two folders, and no desktop one.
  int folders = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cache.path())) folders += entry.is_directory() ? 1 : 0;
  EXPECT_EQ(folders, 2);
  // The jobs fovlab prerender runs for the two eyes: one sequence an eye.
  const std::vector<PathTraceFrameJob> jobs = path_traced_frame_jobs({pt}, {eye_of(0), eye_of(1)});
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].sequence.description(), left_sequence.description());
  EXPECT_EQ(jobs[1].sequence.description(), right_sequence.description());
}

// The conversions that take a display take the eye's when given (stimulus_settings.h), and the
// desktop's are unchanged without one.
TEST(EyeStimulusSettings, EveryDisplayIsTheEyesImagePlane) {
  const EyeView eye = eye_of(0);
  const DisplayGeometry eye_plane = eye_display(eye, kWidthPx, kHeightPx);
  ASSERT_NE(eye_plane.principal_offset_x_px, 0.0);
  const StimulusSpec fipr = spec_of(RenderMethod::foveated_pyramid, "primitives");
  const DisplayGeometry stand_in = stimulus_display(fipr);
  EXPECT_EQ(stand_in.width_mm, 300.0);
  EXPECT_EQ(stand_in.principal_offset_x_px, 0.0);
  const DisplayGeometry seen = stimulus_display(fipr, eye);
  EXPECT_EQ(seen.principal_offset_x_px, eye_plane.principal_offset_x_px);
  EXPECT_EQ(seen.width_mm, eye_plane.width_mm);
  EXPECT_EQ(seen.viewing_distance_mm, eye_plane.viewing_distance_mm);

  const SphereTraceSettings traced = sphere_trace_settings(fipr, 0, eye);
  EXPECT_EQ(traced.eye, eye);
  EXPECT_EQ(traced.foveation.display.principal_offset_y_px, eye_plane.principal_offset_y_px);
  EXPECT_FALSE(sphere_trace_settings(fipr, 0).eye);
  EXPECT_EQ(sphere_trace_settings(spec_of(RenderMethod::ground_truth, "primitives"), 0, eye).eye, eye);

  const StimulusSpec fvolume = spec_of(RenderMethod::foveated_volume_raycast, "marschner-lobb");
  const double sigma_deg = std::get<FoveatedVolumeRaycastParameters>(fvolume.parameters).density_sigma_deg;
  EXPECT_EQ(voronoi_mask_settings(fvolume, eye).density_sigma_px, density_sigma_px(eye_plane, sigma_deg));
  EXPECT_NE(voronoi_mask_settings(fvolume, eye).density_sigma_px, voronoi_mask_settings(fvolume).density_sigma_px);
  EXPECT_EQ(volume_render_settings(fvolume, 0, eye).eye, eye);
  EXPECT_FALSE(volume_render_settings(fvolume, 0).eye);

  // A model on a display (the hyperbolic layers, equalised): its map, the equalise solution
  // included, on the eye's plane.
  StimulusSpec layers = spec_of(sampled_method(0, SamplingModel::hyperbolic), "primitives");
  const SamplingMap on_eye = sampling_map(layers, 10.0, 12.0, nullptr, eye);
  const SamplingMap on_stand_in = sampling_map(layers, 10.0, 12.0);
  int differing_px = 0;
  for (int y = 0; y < kHeightPx; ++y)
    for (int x = 0; x < kWidthPx; ++x)
      differing_px += density(on_eye, x + 0.5, y + 0.5) != density(on_stand_in, x + 0.5, y + 0.5) ? 1 : 0;
  EXPECT_GT(differing_px, kWidthPx * kHeightPx / 10);
  const SamplingMap centre = sampling_map(layers, std::nan(""), std::nan(""), nullptr, eye);
  EXPECT_EQ(density(sampling_map(layers, 10.0, 12.0, &centre, eye), 40.0, 30.0), density(on_eye, 40.0, 30.0));
  EXPECT_EQ(density(*sphere_trace_settings(layers, 0, eye).sampling, 40.0, 30.0), density(centre, 40.0, 30.0));
}

}  // namespace
}  // namespace fovlab
