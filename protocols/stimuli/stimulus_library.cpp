#include "protocols/stimuli/stimulus_library.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/content_hash.h"
#include "core/input_error.h"
#include "core/memory_budget.h"
#include "renderer/foveated_sampling/frame_sampler.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/scene/scene_source.h"
#include "renderer/sphere_tracing/sphere_tracer.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"
#include "renderer/volume/volume_raycaster.h"
#include "renderer/volume/volume_scene.h"
#include "renderer/zone_blend/zone_blender.h"

namespace fovlab {
std::string frame_hash(const Rgba8Frame& frame) {
  return ContentHash()
      .add(std::string_view(reinterpret_cast<const char*>(frame.rgba.data()), frame.rgba.size()))
      .hex();
}

StimulusLibrary::StimulusLibrary(vk::Context& context, const std::filesystem::path& cache_root)
    : context_(context), frame_cache_(std::make_unique<FrameCache>(context, cache_root)),
      readback_(std::make_unique<vk::Buffer>()) {}
StimulusLibrary::~StimulusLibrary() = default;

SphereTracer& StimulusLibrary::tracer_for(const std::string& scene) {
  auto found = tracers_.find(scene);
  if (found == tracers_.end())
    found = tracers_.emplace(scene, std::make_unique<SphereTracer>(context_, load_scene(scene))).first;
  return *found->second;
}

PreparedFrame StimulusLibrary::render_live(const StimulusSpec& spec, const StimulusImage& image) {
  const auto start = std::chrono::steady_clock::now();
  PreparedFrame rendered;
  if (spec.method() == RenderMethod::path_traced) {
    rendered.image = render_path_traced(spec, image);
    rendered.hash = frame_hash(rendered.image);
  } else if (spec.method() == RenderMethod::foveated_path_traced) {
    rendered.on_device = blend_foveated_path_traced(spec, image);
  } else if (is_path_traced(spec.method())) {
    rendered.on_device = sample_path_traced(spec, image);
  } else if (is_volume(spec.method())) {
    rendered.on_device = render_volume(spec, image);
  } else {
    rendered.on_device = render_sphere_traced(spec, image);
  }
  render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return rendered;
}

PreparedFrame StimulusLibrary::render(const StimulusSpec& spec, const StimulusImage& image) {
  PreparedFrame rendered = render_live(spec, image);
  if (rendered.on_device) {
    rendered.image = read_back(rendered.on_device, *readback_);
    rendered.hash = frame_hash(rendered.image);
    rendered.on_device = DeviceRgba8Frame{};  // the buffer is the renderer's, reused by the next render
  }
  return rendered;
}

const std::string& StimulusLibrary::hash(const PreparedFrame& frame) {
  if (!frame.hash.empty()) return frame.hash;
  if (&frame != &live_ || !live_.on_device) throw std::logic_error("StimulusLibrary::hash: not the last live frame");
  live_.image = read_back(live_.on_device, *readback_);
  live_.hash = frame_hash(live_.image);
  return live_.hash;
}

DeviceRgba8Frame StimulusLibrary::render_sphere_traced(const StimulusSpec& spec, const StimulusImage& image) {
  SphereTracer& tracer = tracer_for(spec.scene);
  SphereTraceSettings settings = sphere_trace_settings(spec, image.frame);
  settings.outputs = TraceOutputs::display;  // encoded on the device; no step counts or mask
  LastImage& last = last_image_[spec.scene];
  const bool sequence = describe(spec.method()).depends_on_gaze;
  const std::string canonical = sequence ? spec.canonical() : std::string();
  if (sequence) {
    check_sequence(last, canonical, image);
    settings.foveation.gaze_x_px = image.gaze.x_px;
    settings.foveation.gaze_y_px = image.gaze.y_px;
    settings.foveation.frame_index = static_cast<uint32_t>(image.image_index);
    if (settings.sampling) settings.sampling = sampling_map(spec, image.gaze.x_px, image.gaze.y_px, &*settings.sampling);
  }
  // A gaze-independent frame overwrites what a sequence would continue from; a failed render
  // leaves nothing to continue from either.
  last = LastImage{};
  const DeviceRgba8Frame frame = tracer.render(settings).display;
  if (sequence) last = LastImage{canonical, image.image_index};
  return frame;
}

void StimulusLibrary::check_sequence(const LastImage& last, const std::string& canonical, const StimulusImage& image) {
  if (image.image_index < 0 ||
      (image.image_index > 0 && (last.canonical != canonical || last.image_index != image.image_index - 1)))
    throw std::logic_error("StimulusLibrary::render: image " + std::to_string(image.image_index) + " of " + canonical +
                           " does not directly follow image " + std::to_string(image.image_index - 1) +
                           " of the same presentation");
}

VolumeRaycaster& StimulusLibrary::raycaster_for(const StimulusSpec& spec) {
  const bool foveated = spec.method() == RenderMethod::foveated_volume_raycast;
  const std::optional<VoronoiMaskSettings> mask = foveated ? std::optional(voronoi_mask_settings(spec)) : std::nullopt;
  const std::string key = mask ? spec.scene + "#" + voronoi_settings_key(*mask) : spec.scene;
  auto found = raycasters_.find(key);
  if (found != raycasters_.end()) return *found->second;
  auto volume = volumes_.find(spec.scene);
  if (volume == volumes_.end()) {
    VolumeScene scene = load_volume_scene(spec.scene);
    VolumeGrid grid = load_scene_volume(scene, volume_limits(context_));
    volume = volumes_.emplace(spec.scene, std::pair{std::move(scene), std::move(grid)}).first;
  }
  auto raycaster = std::make_unique<VolumeRaycaster>(context_, volume->second.first, volume->second.second);
  // Made anew, never read from the Voronoi cache: a cache file passes every check of its own bytes
  // once its hash and reach are recomputed after an edit, and a participant must see the mask the
  // algorithm makes (so replay, which makes it too, compares frames with the algorithm's). It takes
  // a fraction of a second at the study configs' sizes (docs/volume-rendering.md, "Cache").
  if (mask) raycaster->set_reconstruction(make_voronoi_reconstruction(*mask));
  return *raycasters_.emplace(key, std::move(raycaster)).first->second;
}

DeviceRgba8Frame StimulusLibrary::render_volume(const StimulusSpec& spec, const StimulusImage& image) {
  VolumeRaycaster& raycaster = raycaster_for(spec);
  VolumeRenderSettings settings = volume_render_settings(spec, image.frame);
  LastImage& last = last_image_["volume:" + spec.scene];
  if (spec.method() == RenderMethod::volume_raycast) {
    last = LastImage{};
    settings.frame_index = static_cast<uint32_t>(image.frame);
    return raycaster.display_full_on_device(settings);
  }
  // fvolume: images in order, each with its own gaze; the temporal smoothing's history starts
  // afresh with each presentation, so a presentation's images depend on nothing rendered before it.
  const std::string canonical = spec.canonical();
  check_sequence(last, canonical, image);
  last = LastImage{};
  if (image.image_index == 0) raycaster.reset_history();
  settings.frame_index = static_cast<uint32_t>(image.image_index);
  const DeviceRgba8Frame frame =
      raycaster.display_foveated_on_device(settings, image.gaze.x_px, image.gaze.y_px, temporal_smoothing(spec));
  last = LastImage{canonical, image.image_index};
  return frame;
}

Rgba8Frame StimulusLibrary::render_path_traced(const StimulusSpec& spec, const StimulusImage& image) {
  const PathTracedFrames frames = path_traced_frames(spec);
  Rgba8Frame frame;
  frame.width = spec.width_px;
  frame.height = spec.height_px;
  // pt: the frame encoded by the shader that encodes fpt's frames, so that the two agree to the
  // byte wherever fpt shows its full-resolution zone.
  frame.rgba = blender().encode_for_display(frame_cache_->frame(frames.sequences[0], image.frame));
  return frame;
}

DeviceRgba8Frame StimulusLibrary::blend_foveated_path_traced(const StimulusSpec& spec, const StimulusImage& image) {
  const PathTracedFrames frames = path_traced_frames(spec);
  // fpt: the zone buffers change with the animation frame, the blend with every gaze sample. No
  // state carries from one image to the next, so any image can be rendered on its own.
  const std::string key = spec.canonical() + "#" + std::to_string(image.frame);
  if (key != blender_frame_) {
    blender_frame_.clear();
    const Image foveal = frame_cache_->frame(frames.sequences[0], image.frame);
    if (frames.sequences.size() > 1) {
      const Image periphery = frame_cache_->frame(frames.sequences[1], image.frame);
      blender().set_frame(foveal, &periphery);
    } else {
      blender().set_frame(foveal);
    }
    blender_frame_ = key;
  }
  // Blended and sRGB-encoded on the GPU. A gaze sample that is not a number (none usable, not even
  // a substitute) shows the frame itself: the full-resolution zone everywhere.
  return blender().display_frame_on_device(stimulus_display(spec), image.gaze.x_px, image.gaze.y_px, zone_bounds(spec));
}

DeviceRgba8Frame StimulusLibrary::sample_path_traced(const StimulusSpec& spec, const StimulusImage& image) {
  // As fpt: the frame is uploaded when the animation frame changes, the map follows every gaze
  // sample, and nothing carries from one image to the next.
  const std::string canonical = spec.canonical();
  const std::string key = canonical + "#" + std::to_string(image.frame);
  if (key != sampler_frame_) {
    sampler_frame_.clear();
    sampler().set_frame(frame_cache_->frame(path_traced_frames(spec).sequences[0], image.frame));
    sampler_frame_ = key;
  }
  if (canonical != sampler_centre_spec_) {  // equalise's solution, solved once a stimulus
    sampler_centre_ = sampling_map(spec, std::nan(""), std::nan(""));
    sampler_centre_spec_ = canonical;
  }
  return sampler().display_frame_on_device(sampling_map(spec, image.gaze.x_px, image.gaze.y_px, &*sampler_centre_),
                                           sampling_filter(spec));
}

FrameSampler& StimulusLibrary::sampler() {
  if (!sampler_) sampler_ = std::make_unique<FrameSampler>(context_);
  return *sampler_;
}

ZoneBlender& StimulusLibrary::blender() {
  if (!blender_) blender_ = std::make_unique<ZoneBlender>(context_);
  return *blender_;
}

namespace {

// Where a study's frame size comes from, for error messages.
const std::string kConfigFrameSize = "display.width_px x display.height_px";

std::string config_frame_size(const StimulusSpec& spec) {
  return kConfigFrameSize + " = " + std::to_string(spec.width_px) + "x" + std::to_string(spec.height_px);
}

}  // namespace

void StimulusLibrary::check_foveated_path_traced(const StimulusSpec& spec) {
  stimulus_display(spec);
  check_zone_bounds(zone_bounds(spec));
}

void StimulusLibrary::check_frame_size(const StimulusSpec& spec) {
  if (is_volume(spec.method())) {
    if (spec.width_px < 1 || spec.height_px < 1 || spec.width_px > kMaxVolumeFrameSidePx || spec.height_px > kMaxVolumeFrameSidePx)
      throw InputError(config_frame_size(spec) + ": expected 1 to " + std::to_string(kMaxVolumeFrameSidePx) +
                       " pixels a side for " + std::string(spec.method_name()));
    return;
  }
  if (!is_path_traced(spec.method())) {
    check_sphere_trace_frame_bytes(context_, spec.width_px, spec.height_px, kConfigFrameSize);
    return;
  }
  try {
    check_path_trace_frame_bytes(context_, spec.width_px, spec.height_px);
    if (spec.method() == RenderMethod::foveated_path_traced) check_zone_frame_size(context_, spec.width_px, spec.height_px);
  } catch (const InputError& error) {
    throw InputError(config_frame_size(spec) + ": " + error.what());
  }
}

void StimulusLibrary::prepare_path_traced(const StimulusSpec& spec, const std::function<void()>& frame_done) {
  if (!describe(spec.method()).depends_on_gaze) return;  // pt frames are loaded (or rendered) by prepare's render loop
  // Every frame on disk and readable before the first trial: missing ones are rendered now (fovlab
  // prerender does the same ahead of time, on as many machines as wanted), a damaged one is an
  // error naming its file now rather than mid-session.
  for (const PathTraceSequence& sequence : path_traced_frames(spec).sequences)
    for (int frame = 0; frame < sequence.frame_count; ++frame) {
      frame_cache_->frame(sequence, frame);
      frame_done();
    }
}

uint64_t prepared_frames_bytes(const std::vector<StimulusSpec>& stimuli) {
  uint64_t bytes = 0;
  for (const StimulusSpec& spec : stimuli)
    if (!describe(spec.method()).depends_on_gaze)
      bytes += uint64_t(spec.width_px) * uint64_t(spec.height_px) * 4 * uint64_t(std::max(spec.frame_count, 0));
  return bytes;
}

void check_prepared_frames_fit(const std::vector<StimulusSpec>& stimuli, const std::string& source) {
  const StimulusSpec* example = nullptr;
  size_t prepared = 0;
  for (const StimulusSpec& spec : stimuli) {
    if (describe(spec.method()).depends_on_gaze) continue;
    ++prepared;
    if (!example || spec.frame_count > example->frame_count) example = &spec;
  }
  if (!example) return;
  std::string what = source.empty() ? std::string() : source + ": ";
  what += std::to_string(prepared) + " prepared stimuli x " + std::to_string(example->frame_count) +
          " frames (stimulus.duration_s x stimulus.frames_per_second) x " + std::to_string(example->width_px) + "x" +
          std::to_string(example->height_px) + " px (display.width_px x display.height_px) x 4 bytes";
  check_memory_fits(prepared_frames_bytes(stimuli), what,
                    "shorten stimulus.duration_s, lower stimulus.frames_per_second or the display size, or use fewer "
                    "levels, variants or blocks");
}

double StimulusLibrary::prepare(const std::vector<std::pair<int, StimulusSpec>>& stimuli,
                                const std::function<void(double)>& progress) {
  const double before = render_seconds_;
  // What can be refused without rendering is refused before anything is rendered.
  std::vector<StimulusSpec> held;
  std::set<int> ids;
  for (const auto& [id, spec] : stimuli)
    if (!prepared_.count(id) && ids.insert(id).second) held.push_back(spec);
  check_prepared_frames_fit(held);
  for (const auto& [id, spec] : stimuli) {
    check_frame_size(spec);
    if (spec.method() == RenderMethod::foveated_path_traced) check_foveated_path_traced(spec);
  }
  // Progress in frames: a stimulus rendered ahead (or a gaze-dependent path-traced one, whose frames
  // are loaded or rendered into the cache) counts its frames, any other one frame.
  double total = 0.0, done = 0.0;
  const auto units = [](const StimulusSpec& spec) {
    const bool frames = !describe(spec.method()).depends_on_gaze || is_path_traced(spec.method());
    return frames ? std::max(1.0, double(spec.frame_count)) : 1.0;
  };
  for (const auto& [id, spec] : stimuli) total += units(spec);
  const auto advance = [&](double amount) {
    done += amount;
    if (progress) progress(std::min(1.0, done / total));
  };
  for (const auto& [id, spec] : stimuli) {
    const double before_stimulus = done;
    if (is_path_traced(spec.method())) {
      const auto start = std::chrono::steady_clock::now();
      prepare_path_traced(spec, [&] { advance(std::max(0.0, std::min(1.0, before_stimulus + units(spec) - done))); });
      if (is_sampling_model(spec.method())) sampling_map(spec, std::nan(""), std::nan(""));  // equalise solves now
      render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (describe(spec.method()).depends_on_gaze) {  // blended or sampled live
        advance(std::max(0.0, before_stimulus + units(spec) - done));
        continue;
      }
    } else if (is_volume(spec.method())) {
      // The volume is loaded and fvolume's mask read or made now, not at the first trial.
      const auto start = std::chrono::steady_clock::now();
      raycaster_for(spec);
      render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (describe(spec.method()).depends_on_gaze) {
        advance(units(spec));
        continue;
      }
    } else if (describe(spec.method()).depends_on_gaze) {
      // Rendered live; bad settings and scene errors come now all the same, not mid-session.
      const auto start = std::chrono::steady_clock::now();
      validate(sphere_trace_settings(spec, 0));
      tracer_for(spec.scene);
      render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      advance(units(spec));
      continue;
    }
    if (prepared_.count(id)) {
      advance(units(spec));
      continue;
    }
    std::vector<PreparedFrame> frames;
    for (int frame = 0; frame < spec.frame_count; ++frame) {
      frames.push_back(render(spec, StimulusImage{frame, 0, {}}));
      advance(1.0);
    }
    prepared_.emplace(id, std::move(frames));
    advance(std::max(0.0, before_stimulus + units(spec) - done));  // a stimulus of no frames still counts its one unit
  }
  return render_seconds_ - before;
}

const PreparedFrame& StimulusLibrary::frame(int id, const StimulusSpec& spec, const StimulusImage& image) {
  const auto found = prepared_.find(id);
  if (found != prepared_.end()) return found->second.at(static_cast<size_t>(image.frame));
  live_ = render_live(spec, image);
  return live_;
}

}  // namespace fovlab
