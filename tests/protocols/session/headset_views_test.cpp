// The header's `headset` (protocols/session/headset_views.h): both kinds of gaze_fixation are written
// and read back as they were, and anything else is refused in one line naming the field.
#include <gtest/gtest.h>

#include <string>

#include "core/input_error.h"
#include "protocols/session/headset_views.h"

namespace fovlab {
namespace {

HeadsetViews views_of(GazeFixation fixation, double distance_mm) {
  HeadsetViews views;
  views.runtime = "fovlab test runtime 0.1.0";
  views.eye_width_px = 64;
  views.eye_height_px = 72;
  for (size_t i = 0; i < 2; ++i) {
    views.eyes[i].position_in_head = {i == 0 ? -0.0315 : 0.0315, 0.0, 0.0};
    views.eyes[i].field_of_view = field_of_view_from_deg(-50.0, 45.0, 50.0, -55.0);
  }
  views.gaze_fixation = fixation;
  views.fixation_distance_mm = distance_mm;
  return views;
}

TEST(HeadsetViews, BothGazeFixationsRoundTripThroughTheHeader) {
  const HeadsetViews depth = views_of(GazeFixation::rendered_depth, 0.0);
  const nlohmann::json depth_json = headset_views_json(depth);
  EXPECT_EQ(depth_json["gaze_fixation"], nlohmann::json({{"kind", "rendered-depth"}}));
  EXPECT_EQ(headset_views_from_json(depth_json, "log:1"), depth);
  EXPECT_EQ(headset_gaze_geometry(depth).fixation_distance_m, 0.0);

  const HeadsetViews plane = views_of(GazeFixation::fixation_distance, 1500.0);
  const nlohmann::json plane_json = headset_views_json(plane);
  EXPECT_EQ(plane_json["gaze_fixation"], nlohmann::json({{"kind", "fixation-distance"}, {"distance_mm", 1500.0}}));
  EXPECT_EQ(headset_views_from_json(plane_json, "log:1"), plane);
  EXPECT_EQ(headset_gaze_geometry(plane).fixation_distance_m, 1.5);
}

TEST(HeadsetViews, AnotherGazeFixationIsRefusedNamingTheField) {
  const nlohmann::json good = headset_views_json(views_of(GazeFixation::rendered_depth, 0.0));
  for (const nlohmann::json& fixation :
       {nlohmann::json({{"kind", "vergence"}}), nlohmann::json({{"kind", "rendered-depth"}, {"distance_mm", 800}}),
        nlohmann::json({{"kind", "fixation-distance"}}), nlohmann::json({{"kind", "fixation-distance"}, {"distance_mm", -1}}),
        nlohmann::json("rendered-depth")}) {
    nlohmann::json bad = good;
    bad["gaze_fixation"] = fixation;
    try {
      headset_views_from_json(bad, "log:1");
      ADD_FAILURE() << "accepted " << fixation.dump();
    } catch (const InputError& error) {
      const std::string message = error.what();
      EXPECT_EQ(message.rfind("log:1: headset.gaze_fixation: expected {\"kind\": \"rendered-depth\"} or", 0), 0u)
          << message;
      EXPECT_EQ(message.find('\n'), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace fovlab
