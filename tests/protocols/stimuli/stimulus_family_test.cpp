// The stimulus families (protocols/stimuli/stimulus_renderer.h): every method is drawn by exactly one
// family's renderer, the one its descriptor's scene kind names.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "protocols/stimuli/stimulus_renderer.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

class StimulusFamilyTest : public test::VulkanTest {};

TEST_F(StimulusFamilyTest, EveryMethodHasExactlyOneFamily) {
  std::vector<std::pair<StimulusFamily, std::unique_ptr<StimulusRenderer>>> renderers;
  for (StimulusFamily family : kStimulusFamilies)
    renderers.emplace_back(family, make_stimulus_renderer(family, context(), "stimuli/cache"));
  for (const MethodDescriptor& method : all_methods()) {
    int drawn_by = 0;
    for (const auto& [family, renderer] : renderers)
      if (renderer->renders(method.method)) {
        ++drawn_by;
        EXPECT_EQ(family, stimulus_family(method.method)) << method.name << ": " << stimulus_family_name(family);
      }
    EXPECT_EQ(drawn_by, 1) << method.name;
  }
  // The families as docs/architecture.md names them.
  EXPECT_EQ(stimulus_family(RenderMethod::foveated_pyramid), StimulusFamily::sphere_traced);
  EXPECT_EQ(stimulus_family(sampled_method(0, SamplingModel::kernel_log_polar)), StimulusFamily::sphere_traced);
  EXPECT_EQ(stimulus_family(RenderMethod::foveated_path_traced), StimulusFamily::path_traced);
  EXPECT_EQ(stimulus_family(sampled_method(1, SamplingModel::linear)), StimulusFamily::path_traced);
  EXPECT_EQ(stimulus_family(RenderMethod::foveated_volume_raycast), StimulusFamily::volume);
  EXPECT_EQ(stimulus_family(sampled_method(2, SamplingModel::rectangular)), StimulusFamily::image_sequence);
}

}  // namespace
}  // namespace fovlab
