#pragma once
// [display] kind = "openxr": a head-mounted display through OpenXR (docs/hmd.md, docs/config.md).
// The headset's geometry is given per eye (image size in pixels, field of view as four signed
// angles), so a study can be checked, planned and simulated on a machine with no runtime.
#include <string>
#include <utility>

#include "core/eye_field_of_view.h"

namespace fovlab {

// Where a study is shown: a desktop window (the default) or a headset through OpenXR.
enum class DisplayKind { window, openxr };
const char* display_kind_name(DisplayKind kind);  // "window", "openxr"


// What the scene shows each eye: the studies' camera paths seen from each eye, the head ignored
// (the papers' sequences were), or the camera moved by the tracked head (poses logged per frame).
enum class HeadsetViewModel { head_locked, head_tracked };
const char* headset_view_model_name(HeadsetViewModel model);  // "head-locked", "head-tracked"

// How the headset's one combined gaze ray becomes a pixel in each eye: through the point where the
// ray meets the rendered scene (its depth), or through a point at a fixed distance along it.
enum class GazeFixation { rendered_depth, fixation_distance };

struct HeadsetDisplayConfig {
  // Each eye's image in pixels, 8..16384: fixed by the config (0, "the runtime's recommendation",
  // is refused when it is read), so that every participant sees stimuli of one size.
  int eye_width_px = 0;
  int eye_height_px = 0;
  EyeFieldOfView left_eye_fov;   // read from left_eye_fov_deg (degrees in the config)
  EyeFieldOfView right_eye_fov;
  double ipd_mm = 63.0;  // the eyes' separation where no runtime gives the views
  HeadsetViewModel view_model = HeadsetViewModel::head_locked;
  GazeFixation gaze_fixation = GazeFixation::rendered_depth;
  double fixation_distance_mm = 0.0;  // gaze_fixation == fixation_distance
  int eye_size_line = 0;              // eye_width_px's line in the config (messages)
};

// One eye's image in angles, from its field of view and size: the image plane at unit distance
// spans tan(left)..tan(right) across and tan(down)..tan(up) up, the forward
// direction meets it at centre_*_px, and a degree there covers pixels_per_degree_* pixels.
// (A stand-in of our own until foveation/'s off-axis display_from_field_of_view serves it.)
struct EyeViewGeometry {
  int width_px = 0;
  int height_px = 0;
  double tan_left = 0.0, tan_right = 0.0, tan_up = 0.0, tan_down = 0.0;
  double centre_x_px = 0.0;  // where the forward direction meets the image (origin top left)
  double centre_y_px = 0.0;
  double pixels_per_degree_x = 0.0;  // at the view's centre
  double pixels_per_degree_y = 0.0;
  double width_deg = 0.0;  // angular size: right_deg - left_deg
  double height_deg = 0.0;
};
EyeViewGeometry eye_view_geometry(const EyeFieldOfView& fov, int width_px, int height_px);

// The pixel (origin top left) where the direction at horizontal_deg (right positive) and
// vertical_deg (up positive) from the eye's forward direction, each an angle along its axis as the
// validation targets are placed, meets the eye's image.
std::pair<double, double> eye_pixel_of_direction(const EyeViewGeometry& eye, double horizontal_deg,
                                                 double vertical_deg);

// The flat display a plan's stimuli are made for, in [display]'s terms, from one eye: its image
// plane at kFieldOfViewPlaneDistanceMm (angles are what count, so the distance is a convention)
// with the eye before its centre. Per-eye off-axis geometry replaces it with per-eye rendering.
struct FlatDisplayOfEye {
  double width_mm = 0.0;
  double height_mm = 0.0;
  double viewing_distance_mm = 0.0;
};
FlatDisplayOfEye flat_display_of_eye(const EyeFieldOfView& fov);

// "[-54, 49, 54, -56] deg": a field of view as the config writes it.
std::string field_of_view_text(const EyeFieldOfView& fov);

}  // namespace fovlab
