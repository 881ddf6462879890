#pragma once
// The pre-render cache of path-traced frames (Polychronakis et al. 2021: reference frames too slow to render live are
// rendered once, then shown at display rate). A sequence (scene, size, samples, bounces, seed,
// camera timing) owns one folder, stimuli/cache/<key>/, named by a content hash of the scene's
// content and every setting that changes a pixel; it holds cache.json (what the folder was made
// for, checked on every use) and one linear-light EXR a frame, frame_000000.exr and on. Frames are
// written atomically (a temporary name, then a rename), so a killed pre-render leaves only whole
// frames and resumes with what is missing. Beside each frame, frame_000000.sha256 is its manifest
// entry: the SHA-256 of the bytes the renderer wrote, in sha256sum's format, put in place before the
// frame is renamed into place (so a kill never leaves a frame without one). A frame changed or
// damaged after it was rendered is told apart from the one that was (a session refuses it, a
// pre-render renders it again, `prerender --verify` lists it); a frame without its .sha256 is
// rendered again, never shown. Every file of the cache is read through the input guard
// (core/input_file.h): a FIFO, a device or a link to one is never opened for reading, and no file is
// read past its cap (a frame's size; 4 KiB for a .sha256). EXR files carry no write time, so
// the same frame rendered twice by the same device and driver is the same bytes. docs/foveated-path-tracing.md
// ("Pre-render cache"), docs/scale-out.md.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "core/image.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/path_scene_source.h"

namespace fovlab {

namespace vk {
class Context;
}

struct PathTraceSequence {
  std::string scene;  // "courtyard" or an OBJ path (renderer/prerender/path_scene_source.h)
  int width_px = 0;
  int height_px = 0;
  int samples_per_pixel = 128;
  int max_bounces = 32;
  uint32_t seed = 1;
  double frames_per_second = 30.0;
  double camera_start_s = 0.0;
  // A headset eye's view (issue 42): the frames as that eye sees the camera path; part of the key,
  // so each eye's frames have a folder of their own. None: the desktop camera's frames.
  std::optional<EyeView> eye;
  int frame_count = 1;  // not part of the key: a longer sequence extends a shorter one's folder

  double frame_time_s(int frame) const { return camera_start_s + frame / frames_per_second; }
  PathTraceSettings settings(int frame) const;
  // Every setting that changes a pixel, as text ("scene=...;size=...;..."), the scene by name; an
  // eye's view last (";eye=position:...;orientation:...;fov_rad:...", exact), absent without one.
  std::string description() const;
  bool operator==(const PathTraceSequence& other) const {
    return description() == other.description() && frame_count == other.frame_count;
  }
};

// The default cache root, relative to the working directory.
inline const std::filesystem::path kDefaultCacheRoot = "stimuli/cache";

// What the cache holds for one frame.
enum class FrameStatus {
  missing,     // no file
  unreadable,  // not an EXR of the sequence's size that decodes in full
  unhashed,    // a frame without its .sha256 (left so by an older fovlab, or a frame replaced and
               // its hash deleted): rendered again, never used
  altered,     // its bytes differ from its .sha256 (or the .sha256 is not one: not a regular file
               // of at most 4 KiB)
  whole,       // decodes, and its bytes match its .sha256
};
const char* frame_status_text(FrameStatus status);

class FrameCache {
 public:
  // The context renders missing frames (frame()); the root is created on first use.
  FrameCache(vk::Context& context, std::filesystem::path root);
  // A cache that is only read and checked (prerender --verify): it creates no folder or cache.json
  // (a sequence without one has every frame missing), and rendering a frame is a logic error.
  explicit FrameCache(std::filesystem::path root);
  ~FrameCache();
  FrameCache(const FrameCache&) = delete;
  FrameCache& operator=(const FrameCache&) = delete;

  // The sequence's folder: loads its scene once (to hash its content), creates the folder and its
  // cache.json, or checks that an existing cache.json was made for this sequence (InputError naming
  // the file otherwise: a cache from other parameters is never used).
  std::filesystem::path folder(const PathTraceSequence& sequence);
  std::filesystem::path frame_file(const PathTraceSequence& sequence, int frame);
  // The frame's manifest entry, frame_NNNNNN.sha256.
  std::filesystem::path hash_file(const PathTraceSequence& sequence, int frame);
  FrameStatus frame_status(const PathTraceSequence& sequence, int frame);
  // The frame can be shown as it is: whole (decodes, and matches its .sha256).
  bool has_frame(const PathTraceSequence& sequence, int frame);
  // Renders the frame, removes an older one, stores its .sha256, then the frame. Returns the
  // render's statistics.
  PathTraceResult render_frame(const PathTraceSequence& sequence, int frame);
  // The frame from the cache, rendered and stored first when it or its .sha256 is missing.
  // InputError naming the file when it is there but not a regular file, unreadable, of another size,
  // or differs from its .sha256 (or the .sha256 is not a regular file of one line).
  Image frame(const PathTraceSequence& sequence, int frame);
  // The OBJ loader's note for a scene (dropped triangles...), empty for built-ins; after folder().
  const std::string& scene_note(const std::string& scene);

 private:
  struct SceneEntry {
    LoadedPathScene loaded;
    std::unique_ptr<PathTracer> tracer;  // made on the first render
  };
  SceneEntry& scene_entry(const std::string& scene);
  vk::Context* context_;  // null: read and check only
  std::filesystem::path root_;
  std::map<std::string, SceneEntry> scenes_;
  std::map<std::string, std::filesystem::path> folders_;  // by description, once checked
};

}  // namespace fovlab
