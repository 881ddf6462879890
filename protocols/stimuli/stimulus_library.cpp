#include "protocols/stimuli/stimulus_library.h"

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/colour.h"
#include "core/content_hash.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"

namespace fovlab {
namespace {

Rgba8Frame to_rgba8(const Image& linear) {
  Rgba8Frame frame(linear.width, linear.height);
  for (size_t pixel = 0; pixel < linear.pixel_count(); ++pixel)
    for (int c = 0; c < 3; ++c) {
      const float encoded = encode_srgb(linear.pixels[pixel * static_cast<size_t>(linear.channels) + static_cast<size_t>(c)]);
      frame.rgba[pixel * 4 + static_cast<size_t>(c)] = static_cast<uint8_t>(std::lround(encoded * 255.0f));
    }
  return frame;
}

}  // namespace

std::string frame_hash(const Rgba8Frame& frame) {
  return ContentHash()
      .add(std::string_view(reinterpret_cast<const char*>(frame.rgba.data()), frame.rgba.size()))
      .hex();
}

StimulusLibrary::StimulusLibrary(vk::Context& context) : context_(context) {}
StimulusLibrary::~StimulusLibrary() = default;

SphereTracer& StimulusLibrary::tracer_for(const std::string& scene) {
  auto found = tracers_.find(scene);
  if (found == tracers_.end())
    found = tracers_.emplace(scene, std::make_unique<SphereTracer>(context_, load_scene(scene))).first;
  return *found->second;
}

PreparedFrame StimulusLibrary::render(const StimulusSpec& spec, const StimulusImage& image) {
  const auto start = std::chrono::steady_clock::now();
  SphereTracer& tracer = tracer_for(spec.scene);
  SphereTraceSettings settings = sphere_trace_settings(spec, image.frame);
  settings.colour_only = true;  // a presented frame needs no step counts or mask
  LastImage& last = last_image_[spec.scene];
  const bool sequence = method_depends_on_gaze(spec.method);
  const std::string canonical = sequence ? spec.canonical() : std::string();
  if (sequence) {
    if (image.image_index < 0 ||
        (image.image_index > 0 && (last.canonical != canonical || last.image_index != image.image_index - 1)))
      throw std::logic_error("StimulusLibrary::render: image " + std::to_string(image.image_index) + " of " +
                             canonical + " does not directly follow image " +
                             std::to_string(image.image_index - 1) + " of the same presentation");
    settings.foveation.gaze_x_px = image.gaze.x_px;
    settings.foveation.gaze_y_px = image.gaze.y_px;
    settings.foveation.frame_index = static_cast<uint32_t>(image.image_index);
  }
  // A gaze-independent frame overwrites what a sequence would continue from; a failed render
  // leaves nothing to continue from either.
  last = LastImage{};
  PreparedFrame prepared;
  prepared.image = to_rgba8(tracer.render(settings).colour_linear);
  if (sequence) last = LastImage{canonical, image.image_index};
  prepared.hash = frame_hash(prepared.image);
  render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return prepared;
}

double StimulusLibrary::prepare(const std::vector<std::pair<int, StimulusSpec>>& stimuli) {
  const double before = render_seconds_;
  for (const auto& [id, spec] : stimuli) {
    if (method_depends_on_gaze(spec.method)) {
      // Rendered live; bad settings and scene errors come now all the same, not mid-session.
      const auto start = std::chrono::steady_clock::now();
      validate(sphere_trace_settings(spec, 0));
      tracer_for(spec.scene);
      render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      continue;
    }
    if (prepared_.count(id)) continue;
    std::vector<PreparedFrame> frames;
    for (int frame = 0; frame < spec.frame_count; ++frame) frames.push_back(render(spec, StimulusImage{frame, 0, {}}));
    prepared_.emplace(id, std::move(frames));
  }
  return render_seconds_ - before;
}

const PreparedFrame& StimulusLibrary::frame(int id, const StimulusSpec& spec, const StimulusImage& image) {
  const auto found = prepared_.find(id);
  if (found != prepared_.end()) return found->second.at(static_cast<size_t>(image.frame));
  live_ = render(spec, image);
  return live_;
}

}  // namespace fovlab
