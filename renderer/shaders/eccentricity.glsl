// Exact eccentricity in the shaders, as foveation/display_geometry.cpp computes it on the
// CPU (the reference): the angle at the eye between the rays to the gaze point and to a point, with
// the eye on the perpendicular through the display's principal point (its centre when viewed
// square-on; off it for a headset eye's asymmetric view). Included by the passes that need it.

// The ray from the eye to a point in pixel coordinates, scaled so its largest component is 1 (keeps
// far off-screen points finite in float).
vec3 ray_from_eye(vec2 point_px, vec2 principal_point_px, vec2 pixel_pitch_mm, float viewing_distance_mm) {
  vec3 r = vec3((point_px - principal_point_px) * pixel_pitch_mm, viewing_distance_mm);
  return r / max(max(abs(r.x), abs(r.y)), abs(r.z));
}

float eccentricity_between_deg(vec3 gaze_ray, vec3 point_ray) {
  return degrees(atan(length(cross(gaze_ray, point_ray)), dot(gaze_ray, point_ray)));
}
