// The pre-render cache of path-traced frames (renderer/prerender/frame_cache.h): one folder per
// sequence, keyed by every setting that changes a pixel (and nothing else), frames rendered on
// demand and stored as EXR, unreadable or wrong-size frames refused with an InputError naming the
// file, a cache.json made for other parameters refused, each frame's .sha256 telling an altered
// frame apart, and the same sequence giving the same bytes.
// Tiny frames (32x20, 2 samples, 2 bounces) so that every render takes a moment on lavapipe.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "core/digest.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "renderer/path_tracing/path_tracer.h"
#include "renderer/prerender/frame_cache.h"
#include "renderer/prerender/path_scene_source.h"
#include "tests/renderer/vulkan_test_fixture.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// The InputError's message, or "" when `body` throws nothing (any other exception fails the test).
template <typename Body>
std::string input_error_of(Body&& body) {
  try {
    body();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

class FrameCacheTest : public test::VulkanTest {
 protected:
  void SetUp() override {
    VulkanTest::SetUp();
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("fovlab-frame-cache-test-" + std::to_string(getpid())) / info->name();
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override {
    VulkanTest::TearDown();
    if (HasFailure()) return;  // kept for a look
    fs::remove_all(root_);
    std::error_code ignored;
    fs::remove(root_.parent_path(), ignored);  // this process's folder, once empty
  }

  // The courtyard, small and quick; the camera moves between frames 0 and 1 (t = 2.0, 2.5 s).
  static PathTraceSequence small_sequence() {
    PathTraceSequence sequence;
    sequence.scene = "courtyard";
    sequence.width_px = 32;
    sequence.height_px = 20;
    sequence.samples_per_pixel = 2;
    sequence.max_bounces = 2;
    sequence.seed = 7;
    sequence.frames_per_second = 2.0;
    sequence.camera_start_s = 2.0;
    sequence.frame_count = 2;
    return sequence;
  }

  fs::path root_;
};

TEST_F(FrameCacheTest, FolderIsStableAndKeyedByEveryPixelSettingButNotFrameCount) {
  const PathTraceSequence base = small_sequence();
  fs::path base_folder;
  {
    FrameCache cache(context(), root_);
    base_folder = cache.folder(base);
    EXPECT_EQ(cache.folder(base), base_folder);
  }
  EXPECT_EQ(base_folder.parent_path(), root_);
  EXPECT_TRUE(fs::is_directory(base_folder));
  EXPECT_TRUE(fs::is_regular_file(base_folder / "cache.json"));
  EXPECT_EQ(FrameCache(context(), root_).folder(base), base_folder) << "a second cache finds the same folder";
  // The same sequence under another root: the same key.
  const fs::path other_root = root_ / "other-root";
  EXPECT_EQ(FrameCache(context(), other_root).folder(base).filename(), base_folder.filename());

  FrameCache cache(context(), root_);
  PathTraceSequence longer = base;
  longer.frame_count = 5;
  EXPECT_EQ(cache.folder(longer), base_folder) << "frame_count is not part of the key";
  EXPECT_EQ(cache.frame_file(longer, 3), base_folder / "frame_000003.exr");

  struct Variant {
    const char* what;
    PathTraceSequence sequence;
  };
  std::vector<Variant> variants;
  const auto add = [&](const char* what, auto&& change) {
    PathTraceSequence sequence = base;
    change(sequence);
    variants.push_back({what, sequence});
  };
  add("seed", [](PathTraceSequence& s) { s.seed = 8; });
  add("samples_per_pixel", [](PathTraceSequence& s) { s.samples_per_pixel = 3; });
  add("max_bounces", [](PathTraceSequence& s) { s.max_bounces = 3; });
  add("width", [](PathTraceSequence& s) { s.width_px = 36; });
  add("height", [](PathTraceSequence& s) { s.height_px = 24; });
  add("width and height swapped", [](PathTraceSequence& s) { std::swap(s.width_px, s.height_px); });
  add("frames_per_second", [](PathTraceSequence& s) { s.frames_per_second = 3.0; });
  add("frames_per_second (tiny change)", [](PathTraceSequence& s) { s.frames_per_second = 2.0000000001; });
  add("camera_start_s", [](PathTraceSequence& s) { s.camera_start_s = 2.25; });
  add("camera_start_s (tiny change)", [](PathTraceSequence& s) { s.camera_start_s = 2.0000000001; });
  add("scene", [](PathTraceSequence& s) {
    s.scene = (fs::path(FOVLAB_SOURCE_DIR) / "tests/fixtures/meshes/three_materials.obj").string();
  });

  std::set<fs::path> folders{base_folder};
  for (const Variant& variant : variants) {
    SCOPED_TRACE(variant.what);
    const fs::path folder = cache.folder(variant.sequence);
    EXPECT_NE(folder, base_folder) << variant.what << " changes pixels, so it must change the folder";
    EXPECT_TRUE(folders.insert(folder).second) << variant.what << ": folder shared with another variant";
    EXPECT_EQ(folder.parent_path(), root_);
    EXPECT_EQ(cache.folder(variant.sequence), folder);
  }
  // Every folder found again by a fresh cache (nothing depends on what one cache object saw first).
  FrameCache fresh(context(), root_);
  for (auto it = variants.rbegin(); it != variants.rend(); ++it) {
    SCOPED_TRACE(it->what);
    EXPECT_TRUE(folders.count(fresh.folder(it->sequence)));
  }
  EXPECT_EQ(fresh.folder(base), base_folder);
}

TEST_F(FrameCacheTest, FrameRendersAMissingFrameStoresItAndReadsItBack) {
  const PathTraceSequence sequence = small_sequence();
  FrameCache cache(context(), root_);
  const fs::path file = cache.frame_file(sequence, 1);
  EXPECT_EQ(file.filename(), "frame_000001.exr");
  EXPECT_FALSE(fs::exists(file));
  EXPECT_FALSE(cache.has_frame(sequence, 1));
  EXPECT_FALSE(cache.has_frame(sequence, 0));

  const Image rendered = cache.frame(sequence, 1);
  ASSERT_EQ(rendered.width, 32);
  ASSERT_EQ(rendered.height, 20);
  ASSERT_GE(rendered.channels, 3);
  ASSERT_TRUE(fs::is_regular_file(file));
  EXPECT_TRUE(cache.has_frame(sequence, 1));
  EXPECT_FALSE(cache.has_frame(sequence, 0)) << "only the frame asked for is rendered";
  EXPECT_FALSE(fs::exists(cache.frame_file(sequence, 0)));
  double sum = 0.0;
  for (float value : rendered.pixels) {
    ASSERT_TRUE(std::isfinite(value));
    sum += value;
  }
  EXPECT_GT(sum, 0.0) << "the courtyard is lit";

  // The file holds exactly the returned image (32-bit float EXR), and the next frame() reads it.
  const Image stored = read_image(file);
  ASSERT_EQ(stored.width, rendered.width);
  ASSERT_EQ(stored.height, rendered.height);
  ASSERT_EQ(stored.channels, rendered.channels);
  EXPECT_EQ(stored.pixels, rendered.pixels);
  EXPECT_EQ(cache.frame(sequence, 1).pixels, rendered.pixels);

  // Beside it, its manifest entry: the SHA-256 of its bytes in sha256sum's format.
  const fs::path hash = cache.hash_file(sequence, 1);
  EXPECT_EQ(hash.filename(), "frame_000001.sha256");
  EXPECT_EQ(read_text(hash), sha256_hex(read_text(file)) + "  frame_000001.exr\n");
  EXPECT_EQ(cache.frame_status(sequence, 1), FrameStatus::whole);

  // A file replaced by another image of the right size no longer matches its .sha256: not a cached
  // frame, and frame() refuses it naming both files (a session never shows an altered stimulus).
  Image marker(32, 20, 3);
  for (size_t i = 0; i < marker.pixels.size(); ++i) marker.pixels[i] = 0.25f + 0.001f * float(i);
  write_image(file, marker);
  FrameCache reopened(context(), root_);
  EXPECT_EQ(reopened.frame_status(sequence, 1), FrameStatus::altered);
  EXPECT_FALSE(reopened.has_frame(sequence, 1));
  const std::string refused = input_error_of([&] { reopened.frame(sequence, 1); });
  EXPECT_NE(refused.find(file.string()), std::string::npos) << refused;
  EXPECT_NE(refused.find("frame_000001.sha256"), std::string::npos) << refused;
  // The replaced frame with its .sha256 deleted: nothing says it is the frame rendered, so it is not
  // a cached frame, and frame() renders it again (and its hash) instead of showing it.
  fs::remove(hash);
  EXPECT_EQ(reopened.frame_status(sequence, 1), FrameStatus::unhashed);
  EXPECT_FALSE(reopened.has_frame(sequence, 1));
  const Image read_back = reopened.frame(sequence, 1);
  EXPECT_EQ(read_back.pixels, rendered.pixels) << "rendered again, not the replaced file";
  EXPECT_EQ(read_image(file).pixels, rendered.pixels) << "the replaced file is replaced in the cache";
  EXPECT_EQ(read_text(hash), sha256_hex(read_text(file)) + "  frame_000001.exr\n");
  EXPECT_EQ(reopened.frame_status(sequence, 1), FrameStatus::whole);

  // Frame 0 is a different camera time: a different image, and the direct render of its settings.
  const Image frame0 = cache.frame(sequence, 0);
  EXPECT_NE(frame0.pixels, rendered.pixels) << "the camera moves between frames";
  PathTracer tracer(context(), load_path_scene(sequence.scene).scene);
  const PathTraceResult direct = tracer.render(sequence.settings(0));
  EXPECT_EQ(direct.image.pixels, frame0.pixels) << "the cache stores the path tracer's frame at start + i / fps";
}

TEST_F(FrameCacheTest, RenderFrameReplacesTheFileAndReportsTheRender) {
  const PathTraceSequence sequence = small_sequence();
  FrameCache cache(context(), root_);
  const fs::path file = cache.frame_file(sequence, 0);
  write_text(file, "not an exr");
  EXPECT_FALSE(cache.has_frame(sequence, 0));
  const PathTraceResult result = cache.render_frame(sequence, 0);
  EXPECT_EQ(result.samples, uint64_t(32 * 20 * 2));
  EXPECT_TRUE(cache.has_frame(sequence, 0));
  EXPECT_EQ(read_image(file).pixels, result.image.pixels);
  // No temporary file is left beside the frames.
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(cache.folder(sequence))) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"cache.json", "frame_000000.exr", "frame_000000.sha256"}));
  EXPECT_EQ(cache.frame_status(sequence, 0), FrameStatus::whole);
}

TEST_F(FrameCacheTest, MissingCorruptOrWrongSizeFramesAreNotCachedAndFrameNamesTheFile) {
  const PathTraceSequence sequence = small_sequence();
  FrameCache cache(context(), root_);
  const fs::path file = cache.frame_file(sequence, 0);
  EXPECT_FALSE(cache.has_frame(sequence, 0)) << "missing";

  // A real frame, to corrupt in several ways.
  const Image good = cache.frame(sequence, 0);
  ASSERT_TRUE(cache.has_frame(sequence, 0));
  const std::string bytes = read_text(file);
  ASSERT_GT(bytes.size(), 64u);

  const auto expect_refused = [&](const std::string& what, bool has_frame_expected_false) {
    SCOPED_TRACE(what);
    if (has_frame_expected_false) {
      EXPECT_FALSE(cache.has_frame(sequence, 0)) << what;
    }
    const std::string message = input_error_of([&] { cache.frame(sequence, 0); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << what << ": " << message;
    // The bad file is left as it was for the user to see (frame() does not silently replace it).
    EXPECT_TRUE(fs::exists(file));
  };

  write_text(file, "this is not an OpenEXR file at all, just text of some length.....");
  expect_refused("not an EXR", true);

  write_text(file, bytes.substr(0, 20));  // cut inside the header
  expect_refused("truncated inside the header", true);

  write_text(file, "");
  expect_refused("empty file", true);

  write_image(file, Image(16, 10, 3));  // a valid EXR of another size
  expect_refused("EXR of another size (16x10)", true);
  write_image(file, Image(20, 32, 3));  // transposed
  expect_refused("EXR of another size (20x32)", true);

  // A wrong-size message says both sizes.
  write_image(file, Image(16, 10, 3));
  const std::string message = input_error_of([&] { cache.frame(sequence, 0); });
  EXPECT_NE(message.find("16x10"), std::string::npos) << message;
  EXPECT_NE(message.find("32x20"), std::string::npos) << message;

  // Cut inside the pixel data: the header is whole, but the frame does not decode in full.
  write_text(file, bytes.substr(0, bytes.size() / 2));
  expect_refused("truncated inside the pixels", true);
  write_text(file, bytes.substr(0, bytes.size() - 8));
  expect_refused("last bytes cut off", true);

  // A good file again: read back as rendered.
  write_text(file, bytes);
  EXPECT_TRUE(cache.has_frame(sequence, 0));
  EXPECT_EQ(cache.frame(sequence, 0).pixels, good.pixels);
}

TEST_F(FrameCacheTest, CacheJsonForOtherParametersIsRefusedNamingIt) {
  const PathTraceSequence sequence = small_sequence();
  fs::path folder;
  {
    FrameCache cache(context(), root_);
    folder = cache.folder(sequence);
  }
  const fs::path manifest = folder / "cache.json";
  const std::string original = read_text(manifest);
  ASSERT_NE(original.find(sequence.description()), std::string::npos) << original;

  // Another sequence's parameters written into this folder's cache.json.
  PathTraceSequence other = sequence;
  other.samples_per_pixel = 64;
  std::string edited = original;
  edited.replace(edited.find(sequence.description()), sequence.description().size(), other.description());
  write_text(manifest, edited);
  {
    FrameCache cache(context(), root_);
    const std::string message = input_error_of([&] { cache.folder(sequence); });
    EXPECT_NE(message.find(manifest.string()), std::string::npos) << message;
    // Everything that goes through folder() is refused too.
    EXPECT_NE(input_error_of([&] { cache.has_frame(sequence, 0); }).find("cache.json"), std::string::npos);
    EXPECT_NE(input_error_of([&] { cache.frame(sequence, 0); }).find("cache.json"), std::string::npos);
    EXPECT_FALSE(fs::exists(folder / "frame_000000.exr")) << "nothing rendered into a folder made for others";
  }

  // Text that is not JSON, and a JSON object without the fields.
  for (const std::string& text : {original.substr(0, original.size() / 2), std::string(""), std::string("{}")}) {
    SCOPED_TRACE(text);
    write_text(manifest, text);
    FrameCache cache(context(), root_);
    const std::string message = input_error_of([&] { cache.folder(sequence); });
    EXPECT_NE(message.find(manifest.string()), std::string::npos) << message;
  }

  // Restored: accepted again.
  write_text(manifest, original);
  FrameCache cache(context(), root_);
  EXPECT_EQ(cache.folder(sequence), folder);
}

// A cache.json that is JSON but not an object, or whose "sequence" is not a string, is still a
// cache.json made for something else: an InputError naming it, not a JSON library exception (which
// the fovlab command reports as an internal error with exit code 1).
TEST_F(FrameCacheTest, CacheJsonOfAnotherShapeIsRefusedNamingIt) {
  const PathTraceSequence sequence = small_sequence();
  fs::path folder;
  {
    FrameCache cache(context(), root_);
    folder = cache.folder(sequence);
  }
  const fs::path manifest = folder / "cache.json";
  for (const std::string& text :
       {std::string("[1, 2, 3]"), std::string("\"text\""), std::string("42"), std::string("{\"sequence\": 5}")}) {
    SCOPED_TRACE(text);
    write_text(manifest, text);
    FrameCache cache(context(), root_);
    std::string message;
    try {
      cache.folder(sequence);
    } catch (const InputError& error) {
      message = error.what();
    } catch (const std::exception& error) {
      ADD_FAILURE() << "not an InputError: " << error.what();
      continue;
    }
    EXPECT_NE(message.find(manifest.string()), std::string::npos) << message;
  }
}

TEST_F(FrameCacheTest, SameSequenceRenderedTwiceGivesIdenticalBits) {
  PathTraceSequence sequence = small_sequence();
  sequence.frame_count = 1;
  std::vector<float> first;
  {
    FrameCache cache(context(), root_ / "a");
    first = cache.frame(sequence, 0).pixels;
  }
  FrameCache cache(context(), root_ / "b");
  const std::vector<float> second = cache.frame(sequence, 0).pixels;
  EXPECT_EQ(first, second);
  EXPECT_EQ(read_image(cache.frame_file(sequence, 0)).pixels, first);
  EXPECT_EQ(read_image(FrameCache(context(), root_ / "a").frame_file(sequence, 0)).pixels, first);
  // Byte for byte, hash included: an EXR holds no write time, so two machines' caches compare equal.
  for (const char* name : {"frame_000000.exr", "frame_000000.sha256"})
    EXPECT_EQ(read_text(cache.folder(sequence) / name), read_text(FrameCache(root_ / "a").folder(sequence) / name))
        << name;
  // render_frame again into the same cache: the same bits on disk.
  cache.render_frame(sequence, 0);
  EXPECT_EQ(read_image(cache.frame_file(sequence, 0)).pixels, first);
  // And another seed is another image (the seed reaches the render).
  PathTraceSequence reseeded = sequence;
  reseeded.seed = 8;
  EXPECT_NE(cache.frame(reseeded, 0).pixels, first);
}

// Bytes this process has read so far (rchar of /proc/self/io: every read(2), whatever the file).
uint64_t bytes_read_so_far() {
  std::ifstream io("/proc/self/io");
  std::string key;
  uint64_t value = 0;
  while (io >> key >> value)
    if (key == "rchar:") return value;
  return 0;
}

// A .sha256 is one sha256sum line: a 30 GiB one (sparse: no disk) was read for 4.4 GB before it was
// refused. Now it is refused from its size, and the frame is not whole.
TEST_F(FrameCacheTest, AHashFileIsReadNoFurtherThanOneLine) {
  const PathTraceSequence sequence = small_sequence();
  {
    FrameCache cache(context(), root_);
    cache.frame(sequence, 0);
    ASSERT_EQ(cache.frame_status(sequence, 0), FrameStatus::whole);
    fs::resize_file(cache.hash_file(sequence, 0), uint64_t(30) << 30);
  }
  FrameCache reader(root_);  // read and check only
  const uint64_t before = bytes_read_so_far();
  EXPECT_EQ(reader.frame_status(sequence, 0), FrameStatus::altered);
  const uint64_t read = bytes_read_so_far() - before;
  EXPECT_LT(read, uint64_t(1) << 20) << "read " << read << " bytes to check a 32x20 frame";
  FrameCache cache(context(), root_);
  const std::string message = input_error_of([&] { cache.frame(sequence, 0); });
  EXPECT_NE(message.find("frame_000000.sha256: not a regular file of at most 4096 bytes"), std::string::npos)
      << message;
}

TEST_F(FrameCacheTest, BadSequenceSettingsAreInputErrors) {
  FrameCache cache(context(), root_);
  PathTraceSequence sequence = small_sequence();
  sequence.samples_per_pixel = 0;
  EXPECT_THROW(cache.folder(sequence), InputError);
  sequence = small_sequence();
  sequence.width_px = 0;
  EXPECT_THROW(cache.folder(sequence), InputError);
  sequence = small_sequence();
  sequence.scene = "primitives";  // a sphere-traced scene, not a path-traced one
  const std::string message = input_error_of([&] { cache.folder(sequence); });
  EXPECT_NE(message.find("primitives"), std::string::npos) << message;
  sequence.scene = (root_ / "missing.obj").string();
  EXPECT_NE(input_error_of([&] { cache.folder(sequence); }).find("missing.obj"), std::string::npos);
  EXPECT_TRUE(fs::is_empty(root_)) << "no folder made for refused settings";
}

}  // namespace
}  // namespace fovlab
