#include "protocols/stimuli/stimulus_library.h"

#include <algorithm>
#include <chrono>
#include <set>
#include <stdexcept>

#include "core/content_hash.h"
#include "core/input_error.h"
#include "core/memory_budget.h"
#include "protocols/stimuli/stimulus_renderer.h"
#include "renderer/vk/buffer.h"
#include "renderer/vk/context.h"

namespace fovlab {
std::string frame_hash(const Rgba8Frame& frame) {
  return ContentHash().add(std::string_view(reinterpret_cast<const char*>(frame.rgba.data()), frame.rgba.size())).hex();
}

StimulusLibrary::StimulusLibrary(vk::Context& context, const std::filesystem::path& cache_root,
                                 std::optional<EyeView> eye, bool head_tracked)
    : context_(context),
      eye_(std::move(eye)),
      head_tracked_(head_tracked),
      readback_(std::make_unique<vk::Buffer>()) {
  if (head_tracked_ && !eye_) throw std::logic_error("StimulusLibrary: a head-tracked library needs an eye's view");
  for (StimulusFamily family : kStimulusFamilies)
    renderers_[family] = make_stimulus_renderer(family, context, cache_root, eye_);
}
StimulusLibrary::~StimulusLibrary() = default;

StimulusRenderer& StimulusLibrary::renderer_for(const StimulusSpec& spec) {
  StimulusRenderer& renderer = *renderers_.at(stimulus_family(spec.method()));
  if (eye_ && !renderer.renders_eye_views()) {
    // The methods an eye's library does show, from the families themselves, so the list stays true.
    std::string shown;
    for (const MethodDescriptor& method : all_methods())
      if (renderers_.at(stimulus_family(method.method))->renders_eye_views())
        shown += (shown.empty() ? "" : ", ") + std::string(method.name);
    throw InputError(std::string(spec.method_name()) +
                     ": a headset study cannot show it yet: per-eye images are not made (a folder of images is one "
                     "view; issue 42); it shows " + shown);
  }
  if (head_tracked_ && !renderer.follows_head())
    throw InputError(std::string(spec.method_name()) +
                     ": display.view_model: a \"head-tracked\" study re-renders every refresh from the head's pose, and " +
                     stimulus_family_name(stimulus_family(spec.method())) +
                     " frames are made ahead for one view (run it \"head-locked\")");
  return renderer;
}

nlohmann::json StimulusLibrary::image_hashes() const {
  nlohmann::json hashes = nlohmann::json::object();
  for (const auto& [family, renderer] : renderers_) hashes.update(renderer->image_hashes());
  return hashes;
}

PreparedFrame StimulusLibrary::render_live(const StimulusSpec& spec, const StimulusImage& image) {
  const auto start = std::chrono::steady_clock::now();
  PreparedFrame rendered = renderer_for(spec).render(spec, image);
  render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return rendered;
}

std::optional<double> StimulusLibrary::surface_distance(const StimulusSpec& spec, int frame,
                                                        const std::array<double, 3>& origin_in_head,
                                                        const std::array<double, 3>& direction_in_head) {
  if (!eye_) throw std::logic_error("StimulusLibrary::surface_distance: a library without an eye's view");
  const StimulusFamily family = stimulus_family(spec.method());
  if (family != StimulusFamily::sphere_traced)
    throw InputError("method " + std::string(describe(spec.method()).name) + ": a " + stimulus_family_name(family) +
                     " stimulus shows no surface for the gaze to rest on");
  return renderer_for(spec).surface_distance(spec, frame, *eye_, origin_in_head, direction_in_head);
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
  // What can be refused without rendering is refused before anything is rendered; first, for an
  // eye, what it cannot show at all (renderer_for).
  if (eye_)
    for (const auto& [id, spec] : stimuli) renderer_for(spec);
  std::vector<StimulusSpec> held;
  std::set<int> ids;
  for (const auto& [id, spec] : stimuli)
    if (!prepared_.count(id) && ids.insert(id).second) held.push_back(spec);
  check_prepared_frames_fit(held);
  for (const auto& [id, spec] : stimuli) renderer_for(spec).validate(spec);
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
    // What the family readies ahead: a scene compiled or loaded, cached frames, a mask or equalise's
    // solution. Gaze-dependent stimuli are then rendered live, the others ahead, below.
    const auto start = std::chrono::steady_clock::now();
    renderer_for(spec).prepare(spec,
                               [&] { advance(std::max(0.0, std::min(1.0, before_stimulus + units(spec) - done))); });
    render_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (describe(spec.method()).depends_on_gaze || head_tracked_) {  // rendered live, a refresh at a time
      // One image now, not shown: what its first refresh would otherwise build mid-trial (the
      // tracer's pipelines for this stimulus's passes, its frame buffers). A presentation's image 0
      // depends on nothing rendered before it, so the session's images are as without it.
      GazeSample centre;
      centre.x_px = 0.5 * spec.width_px;
      centre.y_px = 0.5 * spec.height_px;
      render_live(spec, StimulusImage{0, 0, centre, {}});
      advance(std::max(0.0, before_stimulus + units(spec) - done));
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
  if (found != prepared_.end() && !image.head) return found->second.at(static_cast<size_t>(image.frame));
  live_ = render_live(spec, image);
  return live_;
}

}  // namespace fovlab
