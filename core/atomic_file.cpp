#include "core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "core/input_error.h"

namespace fovlab {

std::filesystem::path temporary_sibling(const std::filesystem::path& target) {
  // Built with += : GCC 12 warns falsely (-Wrestrict) on a chain of string operator+.
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-";
  name += std::to_string(::getpid());
  name += target.extension().string();
  return target.parent_path() / name;
}

namespace {
void sync_file(const std::filesystem::path& path) {
  int fd = ::open(path.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}
}  // namespace

void fsync_directory(const std::filesystem::path& directory) {
  const int fd = ::open(directory.empty() ? "." : directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write_to) {
  const std::filesystem::path temporary = temporary_sibling(target);
  try {
    write_to(temporary);
    sync_file(temporary);
    std::filesystem::rename(temporary, target);
    fsync_directory(target.parent_path());  // the rename itself survives a power cut
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void write_text_atomically(const std::filesystem::path& target, std::string_view text) {
  write_atomically(target, [&](const std::filesystem::path& temporary) {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw InputError(target.string() + ": cannot write file");
  });
}

}  // namespace fovlab
