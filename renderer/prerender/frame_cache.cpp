#include "renderer/prerender/frame_cache.h"

#include <array>

#include <cstdio>
#include <optional>
#include <stdexcept>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/digest.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "core/number_text.h"

namespace fovlab {

namespace {

constexpr const char* kCacheFormat = "fovlab-frame-cache-1";
constexpr uint64_t kMaxManifestBytes = 64 * 1024;  // cache.json: three short fields

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

// A .sha256 is one sha256sum line: 64 hex digits, two spaces and the frame's name.
constexpr uint64_t kMaxHashFileBytes = 4096;
constexpr const char* kFrameExpected =
    "a frame of the pre-render cache (an EXR fovlab prerender wrote; delete it to render it again)";

// The most a frame's file may hold: its pixels as 32-bit floats, RGBA, twice over (OpenEXR's
// compression never doubles them), and 1 MiB for its header and offset tables.
uint64_t max_frame_file_bytes(const PathTraceSequence& sequence) {
  return 2 * uint64_t(sequence.width_px) * uint64_t(sequence.height_px) * 4 * sizeof(float) + (uint64_t(1) << 20);
}

enum class HashVerdict { missing, not_a_hash_file, differs, matches };

// The frame's bytes against its .sha256. No path that is there is "missing" (a FIFO, a device, a link
// to one, or a file larger than one line is not a hash file), and no more than its cap is read.
HashVerdict check_hash(std::string_view frame_bytes, const std::filesystem::path& file,
                       const std::filesystem::path& hash) {
  std::error_code error;
  if (!std::filesystem::exists(std::filesystem::symlink_status(hash, error))) return HashVerdict::missing;
  const std::optional<std::string> line = read_file_if_regular(hash, kMaxHashFileBytes);
  if (!line) return HashVerdict::not_a_hash_file;
  return *line == hash_line(frame_bytes, file) ? HashVerdict::matches : HashVerdict::differs;
}

bool is_there(const std::filesystem::path& path) {
  std::error_code error;
  return std::filesystem::exists(std::filesystem::symlink_status(path, error));
}

}  // namespace

const char* frame_status_text(FrameStatus status) {
  switch (status) {
    case FrameStatus::missing:
      return "missing";
    case FrameStatus::unreadable:
      return "not a whole EXR of the sequence's size";
    case FrameStatus::unhashed:
      return "no .sha256 beside it";
    case FrameStatus::altered:
      return "its bytes differ from its .sha256";
    case FrameStatus::whole:
      return "whole";
  }
  return "?";
}

namespace {

// An eye's view as the sequence's key writes it: every number exactly (17 significant digits).
std::string eye_view_text(const EyeView& eye) {
  const auto numbers = [](const auto& values) {
    std::string text;
    for (const double value : values) text += (text.empty() ? "" : ",") + format_number(value, 17);
    return text;
  };
  const EyeFieldOfView& fov = eye.field_of_view;
  return "position:" + numbers(eye.position_in_head) + ";orientation:" + numbers(eye.orientation_in_head) +
         ";fov_rad:" +
         numbers(std::array{fov.angle_left_rad, fov.angle_right_rad, fov.angle_up_rad, fov.angle_down_rad});
}

}  // namespace

PathTraceSettings PathTraceSequence::settings(int frame) const {
  PathTraceSettings settings;
  settings.width_px = width_px;
  settings.height_px = height_px;
  settings.samples_per_pixel = samples_per_pixel;
  settings.max_bounces = max_bounces;
  settings.seed = seed;
  settings.time_s = frame_time_s(frame);
  settings.eye = eye;
  return settings;
}

std::string PathTraceSequence::description() const {
  return "scene=" + scene + ";size=" + size_text(width_px, height_px) +
         ";samples_per_pixel=" + std::to_string(samples_per_pixel) + ";max_bounces=" + std::to_string(max_bounces) +
         ";seed=" + std::to_string(seed) + ";frames_per_second=" + format_number(frames_per_second, 17) +
         ";camera_start_s=" + format_number(camera_start_s, 17) + (eye ? ";eye=" + eye_view_text(*eye) : "");
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
  const nlohmann::json expected = {
      {"format", kCacheFormat}, {"scene_content_hash", scene_hash}, {"sequence", description}};
  std::error_code error;
  if (std::filesystem::exists(manifest, error)) {
    nlohmann::json found;
    try {
      found = nlohmann::json::parse(read_input_file(
          manifest, "the pre-render cache's description (cache.json; delete the folder to render it again)",
          kMaxManifestBytes));
    } catch (const nlohmann::json::exception&) {
      throw InputError(manifest.string() +
                       ": not JSON; expected the pre-render cache's description (delete the folder)");
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
  if (!is_there(file)) return FrameStatus::missing;
  // Read once through the input guard (a FIFO, a device or a link to one is not a frame, and no more
  // than a frame's size is read), then decoded in full from those bytes: a damaged file with a good
  // header is not done, and the bytes hashed are the bytes decoded.
  const std::optional<std::string> bytes = read_file_if_regular(file, max_frame_file_bytes(sequence));
  if (!bytes) return FrameStatus::unreadable;
  try {
    if (!is_frame_of(decode_image(*bytes, file.string()), sequence)) return FrameStatus::unreadable;
  } catch (const InputError&) {
    return FrameStatus::unreadable;
  }
  switch (check_hash(*bytes, file, hash_file(sequence, frame))) {
    case HashVerdict::missing:
      return FrameStatus::unhashed;
    case HashVerdict::matches:
      return FrameStatus::whole;
    case HashVerdict::not_a_hash_file:
    case HashVerdict::differs:
      return FrameStatus::altered;
  }
  return FrameStatus::altered;
}

bool FrameCache::has_frame(const PathTraceSequence& sequence, int frame) {
  return frame_status(sequence, frame) == FrameStatus::whole;
}

PathTraceResult FrameCache::render_frame(const PathTraceSequence& sequence, int frame) {
  const std::filesystem::path file = frame_file(sequence, frame);
  SceneEntry& entry = scene_entry(sequence.scene);
  if (!context_) throw std::logic_error("FrameCache: rendering " + file.string() + " without a Vulkan context");
  if (!entry.tracer) entry.tracer = std::make_unique<PathTracer>(*context_, entry.loaded.scene);
  PathTraceResult result = entry.tracer->render(sequence.settings(frame));
  // The frame's .sha256 (of the encoded bytes) is put in place before the frame itself, and an older
  // frame there is removed first: a kill at any moment leaves no frame without its hash and no older
  // frame beside the new hash (which would read as a frame changed after it was rendered); at worst
  // a hash without its frame, rendered again.
  const std::string bytes = encode_image(result.image, file);
  std::error_code absent_already;
  std::filesystem::remove(file, absent_already);
  write_text_atomically(hash_file(sequence, frame), hash_line(bytes, file));
  write_text_atomically(file, bytes);
  return result;
}

Image FrameCache::frame(const PathTraceSequence& sequence, int frame) {
  const std::filesystem::path file = frame_file(sequence, frame);
  const std::filesystem::path hash = hash_file(sequence, frame);
  // A frame without its .sha256 is rendered again, never shown: nothing says it is the one rendered
  // (a frame replaced and its hash deleted, or one an older fovlab left without its hash).
  if (!is_there(file) || !is_there(hash)) return render_frame(sequence, frame).image;
  const std::string bytes = read_input_file(file, kFrameExpected, max_frame_file_bytes(sequence));
  Image image = decode_image(bytes, file.string());  // InputError naming the file when it cannot be decoded
  if (!is_frame_of(image, sequence))
    throw InputError(file.string() + ": " + size_text(image.width, image.height) + " with " +
                     std::to_string(image.channels) + " channels; expected a " +
                     size_text(sequence.width_px, sequence.height_px) + " RGB frame of the pre-render cache");
  switch (check_hash(bytes, file, hash)) {
    case HashVerdict::matches:
      return image;
    case HashVerdict::missing:
      return render_frame(sequence, frame).image;  // removed since the check above
    case HashVerdict::not_a_hash_file:
      throw InputError(hash.string() + ": not a regular file of at most " + byte_size_text(kMaxHashFileBytes) +
                       ": expected the sha256sum line of " + file.filename().string() +
                       " (delete both files to render the frame again)");
    case HashVerdict::differs:
      break;
  }

  throw InputError(file.string() + ": its bytes differ from " + hash.filename().string() +
                   " (changed after it was rendered); expected the frame fovlab prerender wrote (delete both "
                   "files to render it again)");
}

}  // namespace fovlab
