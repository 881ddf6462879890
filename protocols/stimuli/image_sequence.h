#pragma once
// A folder of the lab's own images as the source of Ye et al. 2022's sampling models (img-rmfr,
// img-hyperbolic, img-linear, img-kfr): the block's `scene` is the folder (relative to the config),
// its .png and .exr files sorted by name are the sequence, and frame i of a presentation shows
// image i (a folder of one image: that image for every frame). The images are read in linear light:
// an EXR as it is, a PNG decoded from sRGB (IEC 61966-2-1), as the path-traced frames' EXRs are
// linear. Each image must be the display's size (display.width_px x display.height_px): the models
// sample it at the display's geometry, pixel for pixel. The session header records each image's
// SHA-256 (image_hashes, log schema 9) and replay refuses a log whose images changed.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/image.h"
#include "study/schedule/study_plan.h"

namespace fovlab {

inline constexpr const char* kImageSequenceExpected = "a folder of .png or .exr images";

// The folder's images (.png and .exr, any case; other files are left out), sorted by file name.
// InputError (one line, naming the folder) when it is missing, not a folder, or holds no image.
std::vector<std::filesystem::path> image_sequence_files(const std::filesystem::path& folder);

struct SequenceImage {
  std::string name;    // the file's name in its folder
  std::string sha256;  // of the file's bytes (lower-case hex)
  Image linear;        // RGB in linear light (a PNG decoded from sRGB; grey repeated; alpha left out)
};

// One image file read, hashed and decoded; InputError naming the file when it cannot be read or decoded.
SequenceImage read_sequence_image(const std::filesystem::path& file);

// The images a stimulus shows read and checked: the folder holds frame_count images or more, or
// one; each of the first frame_count decodes and is width_px x height_px (the others are not read);
// they fit in the memory available. InputError naming the file (or the folder) and what was expected.
std::vector<SequenceImage> read_image_sequence(const std::filesystem::path& folder, int width_px, int height_px,
                                               int frame_count);

// What a session shows of a folder and records of it, from one reading of each file: the images
// the frames show (read_image_sequence) and every image of the folder by name -> SHA-256 (those
// shown: of the very bytes decoded), as image_sequence_hashes gives it. The session header's
// image_hashes come from here, so the log names the bytes the participant saw.
struct LoadedImageSequence {
  std::vector<SequenceImage> shown;
  nlohmann::json hashes = nlohmann::json::object();
};
LoadedImageSequence load_image_sequence(const std::filesystem::path& folder, int width_px, int height_px,
                                        int frame_count);

// The image an animation frame shows: image `frame`, or the only one.
size_t sequence_image_index(size_t image_count, int frame);

// The folder's images by name -> SHA-256 of their bytes (read, not decoded).
nlohmann::json image_sequence_hashes(const std::filesystem::path& folder);

// Every image folder the plan's stimuli show -> image_sequence_hashes; an empty object when none.
nlohmann::json plan_image_hashes(const StudyPlan& plan);

// Replay and resume: InputError (one line, starting with `source`, naming the image) when an image
// the log recorded (`recorded`: its header's image_hashes) is missing or its bytes changed, or the
// folder now holds an image the log did not record; `current` is the folders' hashes now
// (plan_image_hashes, or what a stimulus library loaded).
void check_image_hashes(const nlohmann::json& recorded, const nlohmann::json& current, const std::string& source);

// Every image stimulus's sequence read and checked (read_image_sequence), each folder once:
// InputError starting with `source` (the config) before anything is rendered or written.
void check_image_sequences(const StudyPlan& plan, const std::string& source);

}  // namespace fovlab
