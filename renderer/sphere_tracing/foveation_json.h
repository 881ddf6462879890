#pragma once
// FIPR's settings and shares of one frame as JSON, the one writer of the "foveation" object that
// fovlab render --stats-json and fovlab bench's FIPR cells both carry (docs/cli.md).
#include <nlohmann/json.hpp>

#include "foveation/display_geometry.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab {

// width_mm, height_mm, viewing_distance_mm, pixels_per_degree_at_centre.
nlohmann::json display_json(const DisplayGeometry& display);

// Every FoveationSettings field of the frame (a missing gaze and an infinite outer periphery as
// null) and its top-level, refreshed and kept shares of `pixels`.
nlohmann::json foveation_json(const FoveationSettings& foveation, const FoveationStats& stats, double pixels);

}  // namespace fovlab
