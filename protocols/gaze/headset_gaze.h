#pragma once
// A headset's gaze in each eye's image (issue 42): the geometry that turns one gaze into a pixel of
// the left eye's image and one of the right eye's, so that each eye's stimulus library
// (protocols/stimuli/stimulus_library.h) gets a gaze in its own image.
//
// Units and frames: metres in the head's frame, whose axes are OpenXR's VIEW space (x right, y up,
// z backwards; the origin between the eyes); the EyeViews' positions are in metres too (a scene unit
// a metre), their orientations turn the head's axes into the eye's. Pixels are those of the
// renderer's EyeView and of GazeSample: continuous coordinates with the origin at the image's top
// left corner, x right, y down, pixel (x, y) covering [x, x + 1) x [y, y + 1), so its centre
// (x + 0.5, y + 0.5) looks along lerp(tan(left), tan(right), (x + 0.5) / width) across and
// lerp(tan(up), tan(down), (y + 0.5) / height) up (renderer/scene/eye_view.h). Positions are not
// rounded and may lie off the image: a session sanitizes each eye's sample (sanitize_gaze), which
// rounds it and marks one off its eye's image off_screen.
#include <array>
#include <optional>
#include <utility>

#include "protocols/gaze/gaze_sample.h"
#include "renderer/scene/eye_view.h"

namespace fovlab {

// Where a point appears in the eye's width_px x height_px image: the image position its ray from the
// eye passes through. nullopt when the point is not in front of the eye (on or behind the plane
// through the eye perpendicular to its forward axis) or a coordinate is not finite.
// std::invalid_argument for a size under 1 pixel.
std::optional<std::pair<double, double>> eye_pixel_of_point(const EyeView& eye, int width_px, int height_px,
                                                            const std::array<double, 3>& point_in_head_m);

// Where a direction (in the head's frame, any length) appears in the eye's image: the image position
// of a point at optical infinity along it, the same direction in every eye. nullopt as
// eye_pixel_of_point (a direction not in front of the eye, or not finite).
std::optional<std::pair<double, double>> eye_pixel_of_direction(const EyeView& eye, int width_px, int height_px,
                                                                const std::array<double, 3>& direction_in_head);

// The unit direction, in the head's frame, from the eye through the image position (x_px, y_px) of
// its width_px x height_px image (positions off the image extend the same plane).
// std::invalid_argument for a size under 1 pixel.
std::array<double, 3> direction_of_eye_pixel(const EyeView& eye, int width_px, int height_px, double x_px, double y_px);

// Both eyes' views ([0] left, [1] right), their images' size (the two eyes' images are alike in
// size) and how far away the gaze rests when nothing else says (metres).
struct HeadsetGazeGeometry {
  std::array<EyeView, 2> eyes;
  int width_px = 0;
  int height_px = 0;
  double fixation_distance_m = 1.0;
};

// Where a ray (origin in the head, metres; direction, any length) meets the fixation plane, the
// fronto-parallel plane distance_m in front of the head (z = -distance_m; the head looks along -z):
// the point the gaze rests on with gaze_fixation = "fixation-distance". nullopt when the ray does
// not reach it going forwards, or does not meet it at a finite point.
std::optional<std::array<double, 3>> point_on_fixation_plane(const std::array<double, 3>& origin_m,
                                                             const std::array<double, 3>& direction, double distance_m);

// A tracker's combined gaze ray (origin in the head, metres; direction, any length) as a sample in
// each eye's image: the fixation point origin + fixation_distance_m * the unit direction, where each
// eye sees it. Each sample is `template_sample` (its time fields) with that position. Both are
// invalid, their positions the template's, when the template is invalid (its reason kept), when the
// ray is not finite or has no direction ("not_finite"), or when the point is not in front of both
// eyes ("off_screen"). std::invalid_argument for a fixation distance that is not positive and
// finite.
std::array<GazeSample, 2> eye_gaze_from_ray(const HeadsetGazeGeometry& geometry, const std::array<double, 3>& origin_m,
                                            const std::array<double, 3>& direction, const GazeSample& template_sample);

// A gaze source that gives pixels (trace, synthetic, mouse) gives the left eye's: the left sample is
// `left` as it is, and the right eye's is where the fixation point appears to it. The fixation point
// is where the left eye's ray through that pixel meets the plane fixation_distance_m in front of
// the head's origin (z = -fixation_distance_m: the plane facing the head, so a point straight ahead
// of the head is the same point eye_gaze_from_ray makes from the head's origin). An invalid `left`
// gives two invalid samples (the right one a copy of it); a position that is not finite two invalid
// "not_finite" ones; a ray that does not reach the plane in front of the eye, or a point not in
// front of the right eye, two invalid "off_screen" ones.
// std::invalid_argument for a fixation distance that is not positive and finite.
std::array<GazeSample, 2> eye_gaze_from_left_eye_pixel(const HeadsetGazeGeometry& geometry, const GazeSample& left);

// The gaze resting on the rendered scene (gaze_fixation = "rendered-depth"): the ray (origin in the
// head, metres; direction, any length) meets the surface shown hit_distance_m along its unit
// direction (the stimulus library's surface_distance), and each eye's sample is where that point
// appears to it; no hit (nullopt: the sky) rests the gaze at optical infinity, the ray's direction
// in each eye (eye_pixel_of_direction). Each sample is `template_sample` (its time fields) with that
// position. Both are invalid, as eye_gaze_from_ray says, for an invalid template, a ray that is not
// finite or has no direction, a distance that is not finite or is negative ("not_finite"), or a
// point not in front of both eyes ("off_screen"). Needs no fixation distance.
std::array<GazeSample, 2> eye_gaze_from_ray_at_depth(const HeadsetGazeGeometry& geometry,
                                                     const std::array<double, 3>& origin_m,
                                                     const std::array<double, 3>& direction,
                                                     std::optional<double> hit_distance_m,
                                                     const GazeSample& template_sample);

// The ray of a source that gives the left eye's pixels (trace, synthetic) for rendered-depth: from
// the left eye's position through that pixel (direction_of_eye_pixel, unit). nullopt for a position
// that is not finite.
std::optional<GazeRay> left_eye_ray_of_pixel(const HeadsetGazeGeometry& geometry, double x_px, double y_px);

// eye_gaze_from_left_eye_pixel resting on the rendered scene: the left sample is `left` as it is, and
// the right eye's is where the point hit_distance_m along the left eye's ray through it
// (left_eye_ray_of_pixel) appears to it, or with no hit (nullopt) the ray's direction at optical
// infinity. Invalid samples as eye_gaze_from_left_eye_pixel (a distance not finite or negative:
// "not_finite"; a point not in front of the right eye: "off_screen"). Needs no fixation distance.
std::array<GazeSample, 2> eye_gaze_from_left_eye_pixel_at_depth(const HeadsetGazeGeometry& geometry,
                                                                const GazeSample& left,
                                                                std::optional<double> hit_distance_m);

}  // namespace fovlab
