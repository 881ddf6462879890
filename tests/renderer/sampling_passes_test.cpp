// The GPU passes of the sampling models (renderer/foveated_sampling) against their CPU references
// (foveation/sampling_map.h): the samples listed, where they lie, and the reconstruction of a frame
// from them; then whole frames through the sphere tracer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include "core/colour.h"
#include "foveation/display_geometry.h"
#include "metrics/image_metrics.h"
#include "renderer/foveated_sampling/sampling_passes.h"
#include "renderer/shaders/shared/sphere_trace_params.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "renderer/vk/submission.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

using test::VulkanTest;

constexpr int kWidth = 96, kHeight = 54;

// A 96x54-pixel display 25 cm wide at 40 cm: 10 degrees of eccentricity are about 27 pixels, so
// the hyperbolic and linear models have all their zones on screen.
DisplayGeometry small_display() { return display_from_size(kWidth, kHeight, 250.0, 140.625, 400.0); }

SamplingMap map_of(SamplingModel model, double gaze_x, double gaze_y) {
  SamplingSettings settings;
  settings.model = model;
  settings.outer_pixel_size_px = 6.0;
  return make_sampling_map(settings, small_display(), gaze_x, gaze_y);
}

struct Gaze {
  double x, y;
};
const Gaze kGazes[] = {{48, 27}, {0, 0}, {96, 54}, {10, 40}, {std::nan(""), std::nan("")}};
const SamplingModel kModels[] = {SamplingModel::rectangular, SamplingModel::hyperbolic, SamplingModel::linear,
                                 SamplingModel::kernel_log_polar};

class SamplingPassesTest : public VulkanTest {
 protected:
  // Runs pass 1a for the map; returns the listed samples.
  std::vector<ListedSample> list_samples(SamplingPasses& passes, const SamplingMap& map,
                                         ResampleFilter filter = ResampleFilter::bilinear) {
    passes.prepare(map, filter);
    vk::Buffer counters(context(), gpu::COUNTER_COUNT * sizeof(uint32_t), vk::MemoryUse::device_local);
    vk::Buffer counters_readback(context(), gpu::COUNTER_COUNT * sizeof(uint32_t), vk::MemoryUse::host_readback);
    vk::OneTimeCommands commands(context());
    vk::PassTimer timer(context(), SamplingPasses::kMaxTimedPasses);
    timer.reset(commands.handle());
    vkCmdFillBuffer(commands.handle(), counters.handle(), 0, VK_WHOLE_SIZE, 0);
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    passes.record_positions(commands.handle(), timer, counters.handle(), gpu::COUNTER_MASKED_PIXELS);
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferCopy region{0, 0, counters.size_bytes()};
    vkCmdCopyBuffer(commands.handle(), counters.handle(), counters_readback.handle(), 1, &region);
    passes.record_readback(commands.handle());
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    commands.submit_and_wait();
    counters_readback.invalidate();
    uint32_t count[gpu::COUNTER_COUNT];
    std::memcpy(count, counters_readback.mapped(), sizeof(count));
    return passes.listed_samples(count[gpu::COUNTER_MASKED_PIXELS]);
  }

  // Gives each listed sample the colour (x / W, y / H, 0.5) of its position and runs pass 2: a
  // pixel whose reconstruction follows the map's forward direction gets about its own position.
  Image reconstruct_positions(SamplingPasses& passes, const std::vector<ListedSample>& samples, int width, int height) {
    const uint64_t entries = std::max<uint64_t>(passes.sample_capacity(), 1);
    std::vector<float> colours(entries * 4, 0.0f);
    for (const ListedSample& sample : samples) {
      float* rgba = &colours[size_t(sample.entry) * 4];
      rgba[0] = sample.x_px / float(width);
      rgba[1] = sample.y_px / float(height);
      rgba[2] = 0.5f;
      rgba[3] = 1.0f;
    }
    vk::Buffer upload(context(), colours.size() * sizeof(float), vk::MemoryUse::host_upload);
    std::memcpy(upload.mapped(), colours.data(), colours.size() * sizeof(float));
    upload.flush();
    const VkDeviceSize frame_bytes = VkDeviceSize(width) * VkDeviceSize(height) * 4 * sizeof(float);
    vk::Buffer frame(context(), frame_bytes, vk::MemoryUse::device_local);
    vk::Buffer frame_readback(context(), frame_bytes, vk::MemoryUse::host_readback);
    vk::OneTimeCommands commands(context());
    vk::PassTimer timer(context(), SamplingPasses::kMaxTimedPasses);
    timer.reset(commands.handle());
    VkBufferCopy region{0, 0, upload.size_bytes()};
    vkCmdCopyBuffer(commands.handle(), upload.handle(), passes.sample_colours(), 1, &region);
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    passes.record_reconstruct(commands.handle(), timer, frame.handle());
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkBufferCopy frame_region{0, 0, frame_bytes};
    vkCmdCopyBuffer(commands.handle(), frame.handle(), frame_readback.handle(), 1, &frame_region);
    vk::memory_barrier(commands.handle(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    commands.submit_and_wait();
    frame_readback.invalidate();
    Image image(width, height, 3);
    const auto* rgba = static_cast<const float*>(frame_readback.mapped());
    for (int p = 0; p < width * height; ++p)
      for (int c = 0; c < 3; ++c) image.pixels[size_t(p) * 3 + size_t(c)] = rgba[size_t(p) * 4 + size_t(c)];
    return image;
  }
};

// Pass 1a lists exactly the samples the CPU reference shades (a float-versus-double tie at a
// boundary may flip one in a thousand), each at the reference position to 1e-3 px.
TEST_F(SamplingPassesTest, ListsTheReferenceSamplesAtTheReferencePositions) {
  SamplingPasses passes(context());
  for (SamplingModel model : kModels) {
    for (const Gaze& gaze : kGazes) {
      const SamplingMap map = map_of(model, gaze.x, gaze.y);
      const std::vector<ListedSample> samples = list_samples(passes, map);
      const uint64_t expected = shaded_samples(map);
      const std::string where =
          std::string(sampling_model_name(model)) + " gaze " + std::to_string(gaze.x) + "," + std::to_string(gaze.y);
      EXPECT_NEAR(double(samples.size()), double(expected), 1.0 + 1e-3 * double(expected)) << where;
      std::set<uint32_t> entries;
      double worst_px = 0.0;
      for (const ListedSample& sample : samples) {
        EXPECT_TRUE(entries.insert(sample.entry).second) << where << ": entry listed twice";
        ASSERT_LT(sample.entry, passes.sample_capacity()) << where;
        EXPECT_GE(sample.footprint_px, 1.0f) << where;
        double x = 0, y = 0;
        if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) {
          std::tie(x, y) = rmfr->to_screen_px(sample.entry % uint32_t(rmfr->buffer_width_px) + 0.5,
                                              sample.entry / uint32_t(rmfr->buffer_width_px) + 0.5);
        } else if (const auto* kfr = std::get_if<KernelLogPolarMapping>(&map)) {
          std::tie(x, y) = kfr->to_screen_px(sample.entry % uint32_t(kfr->buffer_width_px) + 0.5,
                                             sample.entry / uint32_t(kfr->buffer_width_px) + 0.5);
        } else if (const auto* layers = std::get_if<HyperbolicLayers>(&map)) {
          uint32_t local = sample.entry;
          int layer = 0;
          for (;; ++layer) {
            const HyperbolicLayer& grid = layers->layers[size_t(layer)];
            const uint32_t count = uint32_t(grid.columns) * uint32_t(grid.rows);
            if (local < count) break;
            local -= count;
          }
          const int columns = layers->layers[size_t(layer)].columns;
          std::tie(x, y) = layers->sample_centre_px(layer, int(local) % columns, int(local) / columns);
        } else {
          x = sample.entry % uint32_t(kWidth) + 0.5;
          y = sample.entry / uint32_t(kWidth) + 0.5;
        }
        worst_px = std::max({worst_px, std::abs(sample.x_px - x), std::abs(sample.y_px - y)});
      }
      EXPECT_LT(worst_px, 1e-3) << where;
    }
  }
}

// RMFR shades every entry of its buffer: pass 1a lists each at its own slot (no atomic a sample) and
// counts them all, whatever the gaze.
TEST_F(SamplingPassesTest, RmfrListsEachEntryAtItsOwnSlot) {
  SamplingPasses passes(context());
  for (const Gaze& gaze : kGazes) {
    const std::vector<ListedSample> samples = list_samples(passes, map_of(SamplingModel::rectangular, gaze.x, gaze.y));
    ASSERT_EQ(samples.size(), size_t(passes.sample_capacity()));
    for (uint32_t slot = 0; slot < samples.size(); ++slot) ASSERT_EQ(samples[slot].entry, slot) << "slot " << slot;
  }
}

// Each model and filter has a pipeline of its own (the shaders take them as constants): one
// SamplingPasses going from model to model and filter to filter rebuilds a frame bit for bit as a
// fresh one does, and the two filters give different frames.
TEST_F(SamplingPassesTest, EachModelAndFilterKeepsItsOwnPipeline) {
  const auto frame_of = [&](SamplingPasses& passes, SamplingModel model, ResampleFilter filter) {
    const SamplingMap map = map_of(model, 30.0, 20.0);
    return reconstruct_positions(passes, list_samples(passes, map, filter), kWidth, kHeight).pixels;
  };
  SamplingPasses shared(context());
  for (SamplingModel model : {SamplingModel::rectangular, SamplingModel::kernel_log_polar, SamplingModel::hyperbolic}) {
    for (ResampleFilter filter : {ResampleFilter::bilinear, ResampleFilter::lanczos2}) {
      const std::string where = std::string(sampling_model_name(model)) + " " + resample_filter_name(filter);
      const std::vector<float> first = frame_of(shared, model, filter);
      SamplingPasses fresh(context());
      EXPECT_TRUE(frame_of(fresh, model, filter) == first) << where;
      const ResampleFilter other = filter == ResampleFilter::bilinear ? ResampleFilter::lanczos2 : ResampleFilter::bilinear;
      EXPECT_FALSE(frame_of(shared, model, other) == first) << where << ": the other filter gave the same frame";
      EXPECT_TRUE(frame_of(shared, model, filter) == first) << where << ": after the other filter";
    }
  }
}

// On an off-axis display (a headset eye's asymmetric view: display_from_field_of_view) the models
// that work in eccentricity (hyperbolic, linear) take it from the principal point on the GPU as the
// CPU reference does: the same samples listed (within the float-versus-double ties above), and not
// the square-on display's.
TEST_F(SamplingPassesTest, OffAxisDisplayListsTheReferenceSamples) {
  SamplingPasses passes(context());
  const double degree = std::numbers::pi / 180.0;
  const DisplayGeometry off_axis =
      display_from_field_of_view(kWidth, kHeight, {-20 * degree, 8 * degree, 5 * degree, -10 * degree});
  const DisplayGeometry square_on =
      display_from_size(kWidth, kHeight, off_axis.width_mm, off_axis.height_mm, off_axis.viewing_distance_mm);
  for (SamplingModel model : {SamplingModel::hyperbolic, SamplingModel::linear}) {
    SamplingSettings settings;
    settings.model = model;
    settings.outer_pixel_size_px = 6.0;
    settings.inner_radius_deg = 3.0;
    settings.outer_radius_deg = 8.0;
    const SamplingMap map = make_sampling_map(settings, off_axis, 30.0, 20.0);
    const uint64_t expected = shaded_samples(map);
    const std::vector<ListedSample> samples = list_samples(passes, map);
    EXPECT_NEAR(double(samples.size()), double(expected), 1.0 + 1e-3 * double(expected)) << sampling_model_name(model);
    EXPECT_NE(expected, shaded_samples(make_sampling_map(settings, square_on, 30.0, 20.0)))
        << sampling_model_name(model);
  }
}

// Pass 2 follows the forward maps: fed each sample's own position as its colour, every pixel
// comes back with about its own position, to within the samples' spacing there (Lanczos-2 too: its
// weights are normalised, so it reproduces a ramp as closely).
TEST_F(SamplingPassesTest, ReconstructionReadsEachPixelFromItsOwnNeighbourhood) {
  SamplingPasses passes(context());
  for (ResampleFilter filter : {ResampleFilter::bilinear, ResampleFilter::lanczos2})
    for (SamplingModel model : kModels) {
      for (const Gaze& gaze : kGazes) {
        const SamplingMap map = map_of(model, gaze.x, gaze.y);
        const Image image = reconstruct_positions(passes, list_samples(passes, map, filter), kWidth, kHeight);
        const std::string where = std::string(sampling_model_name(model)) + " " + resample_filter_name(filter) +
                                  " gaze " + std::to_string(gaze.x) + "," + std::to_string(gaze.y);
        double worst_excess_px = -1e9;
        for (int y = 0; y < kHeight; ++y) {
          for (int x = 0; x < kWidth; ++x) {
            const double got_x = image.at(x, y, 0) * kWidth, got_y = image.at(x, y, 1) * kHeight;
            ASSERT_TRUE(std::isfinite(got_x) && std::isfinite(got_y)) << where;
            EXPECT_FLOAT_EQ(image.at(x, y, 2), 0.5f) << where << " pixel " << x << "," << y << ": no sample reached it";
            // The samples' spacing around the pixel: 1 / sqrt(density), at least a pixel; the linear
            // model's holes are filled from pull-push levels up to a few spacings wide.
            // (RMFR's spacing differs between the axes: the wider one.)
            const double d = density(map, x + 0.5, y + 0.5);
            double spacing = d > 0 ? std::max(1.0, 1.0 / std::sqrt(d)) : 4.0;
            if (const auto* rmfr = std::get_if<RectangularMapping>(&map)) {
              spacing = std::max({1.0, double(kWidth) / (rmfr->buffer_width_px * rmfr->x.density((x + 0.5) / kWidth)),
                                  double(kHeight) / (rmfr->buffer_height_px * rmfr->y.density((y + 0.5) / kHeight))});
            }
            const double allowed = (model == SamplingModel::linear ? 3.0 : 1.5) * spacing + 0.5;
            const double off = std::hypot(got_x - (x + 0.5), got_y - (y + 0.5));
            worst_excess_px = std::max(worst_excess_px, off - allowed);
          }
        }
        EXPECT_LE(worst_excess_px, 0.0) << where;
      }
    }
}

// Whole frames: every model shades the samples its reference counts, its frame stays finite and
// close to GT where the gaze rests, and it takes far fewer steps than GT.
TEST_F(SamplingPassesTest, SphereTracerShadesOnlyTheModelsSamples) {
  SphereTracer tracer(context(), load_scene("primitives"));
  SphereTraceSettings settings;
  settings.width = 160;
  settings.height = 90;
  const SphereTraceResult gt = tracer.render(settings);
  const DisplayGeometry display = display_from_size(160, 90, 400.0, 225.0, 600.0);
  for (SamplingModel model : kModels) {
    SamplingSettings sampling;
    sampling.model = model;
    settings.method = TraceMethod::sampling_model;
    settings.sampling = make_sampling_map(sampling, display, 80, 45);
    const SphereTraceResult result = tracer.render(settings);
    const std::string name = sampling_model_name(model);
    EXPECT_NEAR(double(result.shaded_samples), double(shaded_samples(*settings.sampling)),
                1.0 + 1e-3 * double(result.shaded_samples))
        << name;
    EXPECT_LT(result.total_steps, gt.total_steps) << name;
    EXPECT_TRUE(std::all_of(result.colour_linear.pixels.begin(), result.colour_linear.pixels.end(), [](float v) {
      return std::isfinite(v) && v >= 0.0f;
    })) << name;
    double mask_sum = 0;
    for (float v : result.mask.pixels) mask_sum += v;
    EXPECT_LE(mask_sum, double(result.shaded_samples)) << name;
    // Around the gaze every model samples at least once a pixel: the centre matches GT closely.
    double centre_error = 0;
    int centre_pixels = 0;
    for (int y = 40; y < 50; ++y)
      for (int x = 75; x < 85; ++x, ++centre_pixels)
        for (int c = 0; c < 3; ++c)
          centre_error += std::abs(result.colour_linear.at(x, y, c) - gt.colour_linear.at(x, y, c));
    EXPECT_LT(centre_error / (3.0 * centre_pixels), 0.05) << name;
  }
}

}  // namespace
}  // namespace fovlab
