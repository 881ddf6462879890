// All-or-nothing file writes: a failed write leaves the old file untouched and no temporary behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/image_io.h"
#include "core/input_error.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

std::filesystem::path fresh_folder(const std::string& name) { return testing::fresh_scratch_folder("fovlab-test-" + name); }

std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(AtomicFile, ReplacesContentAndLeavesNoTemporary) {
  const auto folder = fresh_folder("atomic-replace");
  const auto target = folder / "stats.json";
  write_text_atomically(target, "old");
  write_text_atomically(target, "new");
  EXPECT_EQ(read_all(target), "new");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 1);
}

TEST(AtomicFile, FailedWriteKeepsTheOldFile) {
  const auto folder = fresh_folder("atomic-failure");
  const auto target = folder / "image.png";
  write_text_atomically(target, "previous content");
  EXPECT_THROW(write_atomically(target,
                                [](const std::filesystem::path& temporary) {
                                  std::ofstream(temporary) << "half";
                                  throw std::runtime_error("writer died halfway");
                                }),
               std::runtime_error);
  EXPECT_EQ(read_all(target), "previous content");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(folder), {}), 1);
}

TEST(ImageIo, PngRoundTripAndErrorsNameThePath) {
  const auto folder = fresh_folder("image-io");
  Image image(4, 3, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(i % 256) / 255.0f;
  write_image(folder / "a.png", image);
  const Image back = read_image(folder / "a.png");
  ASSERT_EQ(back.width, 4);
  ASSERT_EQ(back.channels, 3);
  for (size_t i = 0; i < image.pixels.size(); ++i) EXPECT_NEAR(back.pixels[i], image.pixels[i], 0.5 / 255.0);

  try {
    read_image(folder / "missing.png");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("missing.png"), std::string::npos);
  }
  EXPECT_THROW(check_output_path(folder / "no-such-folder" / "x.png", "--out"), InputError);
  EXPECT_THROW(check_output_path(folder, "--out"), InputError);
  EXPECT_NO_THROW(check_output_path(folder / "x.png", "--out"));
}

TEST(ContentHash, IsStableAndSeparatesParts) {
  // FNV-1a of the empty input with our length suffix is a fixed value on every platform.
  EXPECT_EQ(ContentHash().add("ab").add("c").hex(), ContentHash().add("ab").add("c").hex());
  EXPECT_NE(ContentHash().add("ab").add("c").value(), ContentHash().add("a").add("bc").value());
  EXPECT_EQ(ContentHash().hex(), "cbf29ce484222325");
  EXPECT_EQ(ContentHash().hex().size(), 16u);
}

}  // namespace
}  // namespace fovlab
