// All-or-nothing file and folder writes: a failed write leaves the old file (or folder) untouched and
// no temporary behind; what killed writers left is cleaned up.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/content_hash.h"
#include "core/image_io.h"
#include "core/output_guard.h"
#include "core/input_error.h"
#include "tests/support/small_disk.h"
#include "tests/support/temp_dir.h"

namespace fovlab {
namespace {

using testing::names_in;
using testing::pid_of_a_finished_process;

std::filesystem::path fresh_folder(const std::string& name) {
  return testing::fresh_scratch_folder("fovlab-test-" + name);
}

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

void write_set(const std::filesystem::path& target, bool replace, const std::string& text) {
  write_folder_atomically(target, replace, [&](const std::filesystem::path& temporary) {
    write_text_atomically(temporary / "a.txt", text);
    write_text_atomically(temporary / "b.txt", text);
  });
}

// What a failed write says: the file, the operation and the system's reason, as an InputError (exit
// code 2), never a bare "cannot write file" or an internal error.
std::string write_error(const std::function<void()>& write) {
  try {
    write();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(AtomicFile, AFullDiskSaysSoAndKeepsTheOldFile) {
  const auto folder = fresh_folder("atomic-full-disk");
  testing::SmallDisk disk(folder / "disk");
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (" << disk.reason() << "); needs root";
  const auto target = folder / "disk" / "stats.json";
  write_text_atomically(target, "old");
  disk.fill(folder / "disk" / "filler");
  const std::string big(256 * 1024, 'x');  // more than the whole disk: the write itself fails
  EXPECT_EQ(write_error([&] { write_text_atomically(target, big); }),
            target.string() + ": writing failed (No space left on device)");
  EXPECT_EQ(read_all(target), "old");
  EXPECT_EQ(names_in(folder / "disk"), (std::vector<std::string>{"filler", "stats.json"}));  // no temporary left

  // A folder of files (fovlab analyze's): the file that did not fit, and why; the old folder kept.
  const auto set = folder / "disk" / "set";
  std::filesystem::remove(folder / "disk" / "filler");
  write_set(set, false, "old set");
  disk.fill(folder / "disk" / "filler");
  const std::string message = write_error([&] { write_set(set, true, big); });
  EXPECT_NE(message.find("a.txt: writing failed (No space left on device)"), std::string::npos) << message;
  EXPECT_EQ(read_all(set / "a.txt"), "old set");

  // An image: OpenImageIO's PNG writer ignored the failed write (an empty file, no error); encoded in
  // memory and written by write_text_atomically, it says so and keeps the old file, in every format.
  std::filesystem::remove(folder / "disk" / "filler");
  std::filesystem::remove_all(set);
  Image noise(256, 256, 4);
  uint32_t state = 1;
  for (float& value : noise.pixels) value = float((state = state * 1664525u + 1013904223u) >> 8) / float(1 << 24);
  for (const char* name : {"frame.png", "frame.exr"}) {
    const auto image_target = folder / "disk" / name;
    write_text_atomically(image_target, "old image");
    disk.fill(folder / "disk" / "filler");
    EXPECT_EQ(write_error([&] { write_image(image_target, noise); }),
              image_target.string() + ": writing failed (No space left on device)");
    EXPECT_EQ(read_all(image_target), "old image");
    std::filesystem::remove(folder / "disk" / "filler");
  }
}

TEST(AtomicFile, ARenameTheSystemRefusesSaysWhy) {
  const auto folder = fresh_folder("atomic-rename");
  const auto target = folder / "taken";
  std::filesystem::create_directories(target / "inside");  // a folder with entries: rename(2) refuses
  const std::string message = write_error([&] { write_text_atomically(target, "text"); });
  EXPECT_EQ(message.rfind(target.string() + ": renaming .taken.tmp-", 0), 0u) << message;
  EXPECT_NE(message.find(" into place failed (Is a directory)"), std::string::npos) << message;
  EXPECT_EQ(names_in(folder), std::vector<std::string>{"taken"});  // the temporary removed
}

// --- whole folders --------------------------------------------------------------------------------

TEST(AtomicFolder, WritesTheSetAndReplacesOnlyWhenAsked) {
  const auto folder = fresh_folder("atomic-folder");
  const auto target = folder / "out";
  write_set(target, false, "first");
  EXPECT_EQ(names_in(folder), std::vector<std::string>{"out"});
  EXPECT_EQ(names_in(target), (std::vector<std::string>{"a.txt", "b.txt"}));
  try {
    write_set(target, false, "second");
    ADD_FAILURE() << "an existing folder was replaced without replace";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(target.string()), std::string::npos) << error.what();
  }
  EXPECT_EQ(read_all(target / "a.txt"), "first");
  write_set(target, true, "third");
  EXPECT_EQ(read_all(target / "a.txt"), "third");
  EXPECT_EQ(read_all(target / "b.txt"), "third");
  EXPECT_EQ(names_in(folder), std::vector<std::string>{"out"}) << "a temporary or the old folder was left";
  // An empty folder is not an earlier set: written without replace.
  std::filesystem::create_directories(folder / "empty");
  write_set(folder / "empty", false, "fourth");
  EXPECT_EQ(read_all(folder / "empty" / "a.txt"), "fourth");
}

TEST(AtomicFolder, FailedWriteKeepsTheOldFolderAndNoTemporary) {
  const auto folder = fresh_folder("atomic-folder-failure");
  const auto target = folder / "out";
  write_set(target, false, "old");
  EXPECT_THROW(write_folder_atomically(target, true,
                                       [](const std::filesystem::path& temporary) {
                                         write_text_atomically(temporary / "a.txt", "half");
                                         throw std::runtime_error("writer died halfway");
                                       }),
               std::runtime_error);
  EXPECT_EQ(read_all(target / "a.txt"), "old");
  EXPECT_EQ(names_in(folder), std::vector<std::string>{"out"});
}

// What killed writers left: temporaries of finished processes are removed, an old folder set aside
// is put back when the target is missing, and the temporaries of a running process are kept.
TEST(AtomicFolder, TemporariesOfKilledWritersAreCleanedUp) {
  const auto folder = fresh_folder("atomic-folder-stale");
  const auto target = folder / "out";
  const std::string dead = std::to_string(pid_of_a_finished_process());
  const std::string alive = std::to_string(::getpid());
  const auto stale = folder / ("out.tmp-" + dead + "-0123456789abcdef");
  const auto running = folder / ("out.tmp-" + alive + "-0123456789abcdef");
  const auto aside = folder / ("out.old-" + dead + "-fedcba9876543210");
  const auto unrelated = folder / "out.tmp-notes";
  for (const auto& path : {stale, running, aside, unrelated}) std::filesystem::create_directories(path);
  write_text_atomically(stale / "a.txt", "half");
  write_text_atomically(aside / "a.txt", "the old set");

  remove_stale_folder_temporaries(target);
  EXPECT_EQ(read_all(target / "a.txt"), "the old set") << "the old folder set aside was not put back";
  EXPECT_FALSE(std::filesystem::exists(stale));
  EXPECT_FALSE(std::filesystem::exists(aside));
  EXPECT_TRUE(std::filesystem::exists(running)) << "a running writer's temporary was removed";
  EXPECT_TRUE(std::filesystem::exists(unrelated));

  // A new write cleans up the same way; an old folder set aside while the target exists is removed.
  std::filesystem::create_directories(aside);
  write_set(target, true, "new");
  EXPECT_EQ(read_all(target / "a.txt"), "new");
  EXPECT_EQ(names_in(folder),
            (std::vector<std::string>{"out", "out.tmp-" + alive + "-0123456789abcdef", "out.tmp-notes"}));
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
  EXPECT_THROW(check_output_target(folder / "no-such-folder" / "x.png", "--out", {OutputKind::image_file}), InputError);
  EXPECT_THROW(check_output_target(folder, "--out", {OutputKind::image_file}), InputError);
  EXPECT_NO_THROW(check_output_target(folder / "x.png", "--out", {OutputKind::image_file}));
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
