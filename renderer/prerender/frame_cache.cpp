#include "renderer/prerender/frame_cache.h"

#include <cstdio>
#include <optional>
#include <stdexcept>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/digest.h"
#include "core/file_bytes.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

constexpr const char* kCacheFormat = "fovlab-frame-cache-1";

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

std::string frame_stem(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d", frame);
  return name;
}

// A manifest entry: sha256sum's line for the file, so `sha256sum -c frame_*.sha256` checks a folder.
std::string hash_line(std::string_view bytes, const std::filesystem::path& file) {
  return sha256_hex(bytes) + "  " + file.filename().string() + "\n";
}

bool is_frame_of(const Image& image, const PathTraceSequence& sequence) {
  return image.width == sequence.width_px && image.height == sequence.height_px && image.channels >= 3;
}

// Whether the frame's bytes match its .sha256; none when it has no .sha256.
std::optional<bool> matches_its_hash(const std::filesystem::path& file, const std::filesystem::path& hash) {
  std::error_code error;
  if (!std::filesystem::exists(hash, error)) return std::nullopt;
  const std::optional<std::string> bytes = read_file_bytes(file);
  return bytes && read_file_bytes(hash) == hash_line(*bytes, file);
}

}  // namespace

const char* frame_status_text(FrameStatus status) {
  switch (status) {
    case FrameStatus::missing: return "missing";
    case FrameStatus::unreadable: return "not a whole EXR of the sequence's size";
    case FrameStatus::unhashed: return "no .sha256 beside it";
    case FrameStatus::altered: return "its bytes differ from its .sha256";
    case FrameStatus::whole: return "whole";
  }
  return "?";
}

PathTraceSettings PathTraceSequence::settings(int frame) const {
  PathTraceSettings settings;
  settings.width_px = width_px;
  settings.height_px = height_px;
  settings.samples_per_pixel = samples_per_pixel;
  settings.max_bounces = max_bounces;
  settings.seed = seed;
  settings.time_s = frame_time_s(frame);
  return settings;
}

std::string PathTraceSequence::description() const {
  return "scene=" + scene + ";size=" + size_text(width_px, height_px) + ";samples_per_pixel=" +
         std::to_string(samples_per_pixel) + ";max_bounces=" + std::to_string(max_bounces) +
         ";seed=" + std::to_string(seed) + ";frames_per_second=" + format_number(frames_per_second, 17) +
         ";camera_start_s=" + format_number(camera_start_s, 17);
}

FrameCache::FrameCache(vk::Context& context, std::filesystem::path root) : context_(&context), root_(std::move(root)) {}
FrameCache::FrameCache(std::filesystem::path root) : context_(nullptr), root_(std::move(root)) {}
FrameCache::~FrameCache() = default;

FrameCache::SceneEntry& FrameCache::scene_entry(const std::string& scene) {
  auto found = scenes_.find(scene);
  if (found == scenes_.end()) found = scenes_.emplace(scene, SceneEntry{load_path_scene(scene), nullptr}).first;
  return found->second;
}

const std::string& FrameCache::scene_note(const std::string& scene) { return scene_entry(scene).loaded.load_note; }

std::filesystem::path FrameCache::folder(const PathTraceSequence& sequence) {
  validate(sequence.settings(0));
  const std::string description = sequence.description();
  if (const auto known = folders_.find(description); known != folders_.end()) return known->second;
  const std::string& scene_hash = scene_entry(sequence.scene).loaded.content_hash;
  // The scene enters by content, so an edited OBJ or a changed built-in gets a new folder.
  const std::string key = ContentHash().add(kCacheFormat).add(scene_hash).add(description).hex();
  const std::filesystem::path folder = root_ / key;
  const std::filesystem::path manifest = folder / "cache.json";
  const nlohmann::json expected = {{"format", kCacheFormat}, {"scene_content_hash", scene_hash},
                                   {"sequence", description}};
  std::error_code error;
  if (std::filesystem::exists(manifest, error)) {
    nlohmann::json found;
    try {
      found = nlohmann::json::parse(read_file_bytes(manifest).value_or(""));
    } catch (const nlohmann::json::exception&) {
      throw InputError(manifest.string() + ": not JSON; expected the pre-render cache's description (delete the folder)");
    }
    if (found != expected) {
      const bool has_sequence = found.is_object() && found.contains("sequence") && found["sequence"].is_string();
      throw InputError(manifest.string() + ": made for other parameters (" +
                       (has_sequence ? found["sequence"].get<std::string>() : std::string("not a cache description")) +
                       "); expected " + description + " (delete the folder to render it again)");
    }
  } else if (context_) {  // a read-only cache (no context) creates nothing: its frames are missing
    std::filesystem::create_directories(folder, error);
    if (error) throw InputError(folder.string() + ": cannot create the cache folder (" + error.message() + ")");
    write_text_atomically(manifest, expected.dump(2) + "\n");
  }
  folders_.emplace(description, folder);
  return folder;
}

std::filesystem::path FrameCache::frame_file(const PathTraceSequence& sequence, int frame) {
  return folder(sequence) / (frame_stem(frame) + ".exr");
}

std::filesystem::path FrameCache::hash_file(const PathTraceSequence& sequence, int frame) {
  return folder(sequence) / (frame_stem(frame) + ".sha256");
}

FrameStatus FrameCache::frame_status(const PathTraceSequence& sequence, int frame) {
  const std::filesystem::path file = frame_file(sequence, frame);
  std::error_code error;
  if (!std::filesystem::exists(file, error)) return FrameStatus::missing;
  try {
    // Decoded in full: a damaged file with a good header is not done.
    if (!is_frame_of(read_image(file), sequence)) return FrameStatus::unreadable;
  } catch (const InputError&) {
    return FrameStatus::unreadable;
  }
  const std::optional<bool> matches = matches_its_hash(file, hash_file(sequence, frame));
  if (!matches) return FrameStatus::unhashed;
  return *matches ? FrameStatus::whole : FrameStatus::altered;
}

bool FrameCache::has_frame(const PathTraceSequence& sequence, int frame) {
  const FrameStatus status = frame_status(sequence, frame);
  return status == FrameStatus::whole || status == FrameStatus::unhashed;
}

void FrameCache::record_hash(const PathTraceSequence& sequence, int frame) {
  const std::filesystem::path file = frame_file(sequence, frame);
  const std::optional<std::string> bytes = read_file_bytes(file);
  if (!bytes) throw InputError(file.string() + ": cannot be read back to hash it");
  write_text_atomically(hash_file(sequence, frame), hash_line(*bytes, file));
}

PathTraceResult FrameCache::render_frame(const PathTraceSequence& sequence, int frame) {
  const std::filesystem::path file = frame_file(sequence, frame);
  SceneEntry& entry = scene_entry(sequence.scene);
  if (!context_) throw std::logic_error("FrameCache: rendering " + file.string() + " without a Vulkan context");
  if (!entry.tracer) entry.tracer = std::make_unique<PathTracer>(*context_, entry.loaded.scene);
  PathTraceResult result = entry.tracer->render(sequence.settings(frame));
  write_image(file, result.image);  // atomic: a temporary file renamed over the target
  record_hash(sequence, frame);     // the bytes as they landed on disk
  return result;
}

Image FrameCache::frame(const PathTraceSequence& sequence, int frame) {
  const std::filesystem::path file = frame_file(sequence, frame);
  std::error_code error;
  if (!std::filesystem::exists(file, error)) return render_frame(sequence, frame).image;
  Image image = read_image(file);  // InputError naming the file when it cannot be decoded
  if (!is_frame_of(image, sequence))
    throw InputError(file.string() + ": " + size_text(image.width, image.height) + " with " +
                     std::to_string(image.channels) + " channels; expected a " +
                     size_text(sequence.width_px, sequence.height_px) + " RGB frame of the pre-render cache");
  const std::filesystem::path hash = hash_file(sequence, frame);
  if (matches_its_hash(file, hash) == false)
    throw InputError(file.string() + ": its bytes differ from " + hash.filename().string() +
                     " (changed after it was rendered); expected the frame fovlab prerender wrote (delete both "
                     "files to render it again)");
  return image;
}

}  // namespace fovlab
