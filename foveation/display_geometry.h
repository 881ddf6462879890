#pragma once
// Where each pixel of a display lies in the viewer's visual field: physical pixel pitch, and the
// exact eccentricity of a pixel from the gaze point (no small-angle approximation). Pure CPU code,
// shared by the foveated renderers (as their reference), the ray-reduction analysis and the study
// runner. Definitions in docs/foveation.md.
//
// Set-up: a flat display of width_mm x height_mm showing width_px x height_px pixels; the eye lies on
// the perpendicular through the display's principal point at viewing_distance_mm. A desktop display
// is viewed square-on: the principal point is its centre. A headset eye's image plane is off-axis
// (display_from_field_of_view): the eye's optical axis meets it off its centre. Pixel (x, y) covers
// [x, x + 1) x [y, y + 1) in pixel coordinates (origin at the top left); its centre is (x + 0.5,
// y + 0.5). The eccentricity of a point is the angle at the eye between the rays to the gaze point
// and to that point.
#include <string>

#include "core/eye_field_of_view.h"

namespace fovlab {

struct DisplayGeometry {
  int width_px = 0;
  int height_px = 0;
  double width_mm = 0.0;
  double height_mm = 0.0;
  double viewing_distance_mm = 0.0;
  // The principal point (where the perpendicular from the eye meets the display's plane) relative to
  // the display's centre, in pixels (x right, y down). 0, 0: viewed square-on, as every desktop display.
  double principal_offset_x_px = 0.0;
  double principal_offset_y_px = 0.0;

  double pixel_pitch_x_mm() const { return width_mm / width_px; }
  double pixel_pitch_y_mm() const { return height_mm / height_px; }
  // The principal point in pixel coordinates; (width_px / 2, height_px / 2) square-on, exactly.
  double principal_point_x_px() const { return 0.5 * width_px + principal_offset_x_px; }
  double principal_point_y_px() const { return 0.5 * height_px + principal_offset_y_px; }
  // Pixels per degree of visual angle at the principal point (horizontal): the derivative there,
  // D * (pi / 180) / pitch_x. Lower away from it; for reporting, not for zone bounds.
  double pixels_per_degree_at_principal_point() const;
  // The same at the display's centre, for a display viewed square-on (where the centre is the
  // principal point): what the desktop commands report.
  double pixels_per_degree_at_centre() const;
};


// A display of the given diagonal (inches) with square pixels. Throws InputError when a value is
// not positive and finite.
DisplayGeometry display_from_diagonal(int width_px, int height_px, double diagonal_in, double viewing_distance_mm);
DisplayGeometry display_from_size(int width_px, int height_px, double width_mm, double height_mm,
                                  double viewing_distance_mm);
// An eye's image plane of width_px x height_px pixels spanning the field of view: the plane
// perpendicular to the eye's forward axis at kFieldOfViewPlaneDistanceMm (a nominal distance: only
// the angles matter), pixel column x at tan-angle lerp(tan(left), tan(right), x / width_px), row y at
// lerp(tan(up), tan(down), y / height_px) (y down), the principal point where the tan-angles are 0.
// Throws InputError unless -90 < left < right < 90 and -90 < down < up < 90 degrees (finite).
DisplayGeometry display_from_field_of_view(int width_px, int height_px, const EyeFieldOfView& field_of_view);

// Eccentricity in degrees of the point (x_px, y_px) (pixel coordinates, as above) when the gaze
// rests on (gaze_x_px, gaze_y_px). Exact: the angle between the two rays from the eye, in [0, 180),
// computed as atan2(|a x b|, a . b) (full precision near 0, unlike acos). Exactly 0 at the gaze
// point; with the gaze at the principal point, atan(d / D) for a point d mm from it. Points and gaze may lie
// off the screen; they are on the display's plane all the same (far points tend to 90 degrees from
// a central gaze, without overflow). Coordinates must be finite (NaN in, NaN out).
double eccentricity_deg(const DisplayGeometry& display, double gaze_x_px, double gaze_y_px, double x_px, double y_px);

}  // namespace fovlab
