#include "protocols/stimuli/image_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <system_error>

#include "core/digest.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "core/input_file.h"
#include "core/memory_budget.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

bool is_sequence_image(const fs::path& file) {
  const std::string extension = lower_extension(file);
  return extension == ".png" || extension == ".exr";
}

// IEC 61966-2-1's sRGB decoding of one value (the inverse of core/colour.h encode_srgb).
float decode_srgb(float encoded) {
  const float value = std::clamp(encoded, 0.0f, 1.0f);
  return value <= 0.04045f ? value / 12.92f : std::pow((value + 0.055f) / 1.055f, 2.4f);
}

// The folders of a plan's image stimuli, each once, with a stimulus that shows it (its size and
// the most frames any of them shows).
struct ImageFolder {
  int width_px = 0, height_px = 0, frame_count = 0;
};
std::map<std::string, ImageFolder> image_folders(const StudyPlan& plan) {
  std::map<std::string, ImageFolder> folders;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    const StimulusSpec& spec = stimulus.spec;
    if (describe(spec.method()).scene_kind != SceneKind::image_sequence) continue;
    ImageFolder& folder = folders[spec.scene];
    folder.width_px = spec.width_px;
    folder.height_px = spec.height_px;
    folder.frame_count = std::max(folder.frame_count, spec.frame_count);
  }
  return folders;
}

}  // namespace

std::vector<fs::path> image_sequence_files(const fs::path& folder) {
  std::error_code error;
  if (!fs::is_directory(folder, error))
    throw InputError(folder.string() + ": no such folder: expected " + kImageSequenceExpected);
  std::vector<fs::path> files;
  for (fs::directory_iterator entry(folder, error), end; !error && entry != end; entry.increment(error))
    if (is_sequence_image(entry->path())) files.push_back(entry->path());
  if (error)
    throw InputError(folder.string() + ": cannot list (" + error.message() + "): expected " + kImageSequenceExpected);
  if (files.empty()) throw InputError(folder.string() + ": no .png or .exr image in it: expected " +
                                      kImageSequenceExpected);
  std::sort(files.begin(), files.end(),
            [](const fs::path& a, const fs::path& b) { return a.filename().string() < b.filename().string(); });
  return files;
}

SequenceImage read_sequence_image(const fs::path& file) {
  const std::string bytes = read_input_file(file, kImageFileExpected, kMaxImageFileBytes);
  const Image decoded = decode_image(bytes, file.string());
  // RGB in linear light: grey (with or without alpha) repeated in each channel, alpha left out; a
  // PNG's values are sRGB-encoded, an EXR's linear.
  const bool srgb = lower_extension(file) == ".png";
  SequenceImage image{file.filename().string(), sha256_hex(bytes), Image(decoded.width, decoded.height, 3)};
  for (int y = 0; y < decoded.height; ++y)
    for (int x = 0; x < decoded.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const float value = decoded.at(x, y, decoded.channels >= 3 ? c : 0);
        image.linear.at(x, y, c) = srgb ? decode_srgb(value) : value;
      }
  return image;
}

namespace {

// read_image_sequence of a listing made once: the images shown, in order.
std::vector<SequenceImage> read_listed_sequence(const fs::path& folder, const std::vector<fs::path>& files,
                                                int width_px, int height_px, int frame_count) {
  if (files.size() != 1 && files.size() < static_cast<size_t>(std::max(frame_count, 1)))
    throw InputError(folder.string() + ": " + std::to_string(files.size()) + " images: expected one (a still) or " +
                     std::to_string(frame_count) +
                     " or more, one a frame (stimulus.duration_s x stimulus.frames_per_second)");
  // Only the images the frames show are read (the others are hashed, not decoded), each held as
  // linear RGB floats for the whole session: refused now if they cannot fit in memory.
  const size_t shown = std::min(files.size(), static_cast<size_t>(std::max(frame_count, 1)));
  check_memory_fits(uint64_t(shown) * uint64_t(std::max(width_px, 0)) * uint64_t(std::max(height_px, 0)) * 3 *
                        sizeof(float),
                    folder.string() + ": " + std::to_string(shown) + " images of " + std::to_string(width_px) + "x" +
                        std::to_string(height_px) + " px as linear RGB floats",
                    "shorten stimulus.duration_s, lower stimulus.frames_per_second or the display size");
  std::vector<SequenceImage> images;
  for (size_t i = 0; i < shown; ++i) {
    const fs::path& file = files[i];
    SequenceImage image = read_sequence_image(file);
    if (image.linear.width != width_px || image.linear.height != height_px)
      throw InputError(file.string() + ": " + std::to_string(image.linear.width) + "x" +
                       std::to_string(image.linear.height) + " pixels: expected " + std::to_string(width_px) + "x" +
                       std::to_string(height_px) +
                       " (display.width_px x display.height_px), the size of every image of the sequence");
    images.push_back(std::move(image));
  }
  return images;
}

std::string file_sha256(const fs::path& file) {
  return sha256_hex(read_input_file(file, kImageFileExpected, kMaxImageFileBytes));
}

}  // namespace

std::vector<SequenceImage> read_image_sequence(const fs::path& folder, int width_px, int height_px, int frame_count) {
  return read_listed_sequence(folder, image_sequence_files(folder), width_px, height_px, frame_count);
}

LoadedImageSequence load_image_sequence(const fs::path& folder, int width_px, int height_px, int frame_count) {
  const std::vector<fs::path> files = image_sequence_files(folder);
  LoadedImageSequence loaded;
  loaded.shown = read_listed_sequence(folder, files, width_px, height_px, frame_count);
  for (const SequenceImage& image : loaded.shown) loaded.hashes[image.name] = image.sha256;
  for (size_t i = loaded.shown.size(); i < files.size(); ++i)
    loaded.hashes[files[i].filename().string()] = file_sha256(files[i]);
  return loaded;
}

size_t sequence_image_index(size_t image_count, int frame) {
  return image_count <= 1 ? 0 : std::min(image_count - 1, static_cast<size_t>(std::max(frame, 0)));
}

nlohmann::json image_sequence_hashes(const fs::path& folder) {
  nlohmann::json hashes = nlohmann::json::object();
  for (const fs::path& file : image_sequence_files(folder))
    hashes[file.filename().string()] = file_sha256(file);
  return hashes;
}

nlohmann::json plan_image_hashes(const StudyPlan& plan) {
  nlohmann::json hashes = nlohmann::json::object();
  for (const auto& [folder, shown] : image_folders(plan)) hashes[folder] = image_sequence_hashes(folder);
  return hashes;
}

void check_image_hashes(const nlohmann::json& recorded, const nlohmann::json& current, const std::string& source) {
  const auto refuse = [&](const std::string& what) { throw InputError(source + ": " + what); };
  for (const auto& [folder, now] : current.items()) {
    const nlohmann::json* logged =
        recorded.is_object() && recorded.contains(folder) ? &recorded.at(folder) : nullptr;
    if (!logged || !logged->is_object())
      refuse("image_hashes records no images of " + folder + ": expected the SHA-256 of each image the session showed");
    for (const auto& [name, hash] : logged->items()) {
      const fs::path file = fs::path(folder) / name;
      if (!now.contains(name))
        refuse(file.string() + ": missing: the session showed it (SHA-256 " + hash.dump() + " in image_hashes)");
      if (now.at(name) != hash)
        refuse(file.string() + ": changed since the session (SHA-256 " + now.at(name).get<std::string>() +
               ", image_hashes " + hash.dump() + "): expected the image the session showed");
    }
    for (const auto& [name, hash] : now.items())
      if (!logged->contains(name))
        refuse((fs::path(folder) / name).string() +
               ": not one of the session's images (image_hashes): expected the folder as the session showed it");
  }
}

void check_image_sequences(const StudyPlan& plan, const std::string& source) {
  for (const auto& [folder, shown] : image_folders(plan)) {
    try {
      read_image_sequence(folder, shown.width_px, shown.height_px, shown.frame_count);
    } catch (const InputError& error) {
      throw InputError(source + ": " + error.what());
    }
  }
}

}  // namespace fovlab
