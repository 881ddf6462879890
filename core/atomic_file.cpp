#include "core/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>  // renameat2 (glibc 2.28+)
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "core/input_error.h"

namespace fovlab {

std::filesystem::path temporary_sibling(const std::filesystem::path& target) {
  // Built with += : GCC 12 warns falsely (-Wrestrict) on a chain of string operator+.
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp-";
  // The host too: tasks on several machines may write the same file of a shared folder at once
  // (fovlab slurm's tasks and a sequence's cache.json), and their process IDs may be equal.
  char host[256] = {};
  if (::gethostname(host, sizeof host - 1) == 0 && host[0] != '\0') {
    name += host;
    name += "-";
  }
  name += std::to_string(::getpid());
  name += target.extension().string();
  return target.parent_path() / name;
}

namespace {
// fsync of a file just written; a failure (a full disk or a write error that surfaces only now, as on
// NFS) is a FileError naming `named` (the file the user asked for) and the system's reason.
void sync_file(const std::filesystem::path& path, const std::filesystem::path& named) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw FileError(named.string(), "opening the written file to fsync it", errno);
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    throw FileError(named.string(), "fsync", error);
  }
  ::close(fd);
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
    sync_file(temporary, target);
    if (::rename(temporary.c_str(), target.c_str()) != 0)
      throw FileError(target.string(), "renaming " + temporary.filename().string() + " into place", errno);
    fsync_directory(target.parent_path());  // the rename itself survives a power cut
  } catch (...) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw;
  }
}

void write_text_atomically(const std::filesystem::path& target, std::string_view text) {
  write_atomically(target, [&](const std::filesystem::path& temporary) {
    // write(2) itself, not a stream: each failure keeps the system's reason (a full disk says so).
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (fd < 0) throw FileError(target.string(), "creating " + temporary.filename().string(), errno);
    size_t written = 0;
    while (written < text.size()) {
      const ssize_t count = ::write(fd, text.data() + written, text.size() - written);
      if (count < 0 && errno == EINTR) continue;
      if (count <= 0) {
        const int error = count < 0 ? errno : EIO;
        ::close(fd);
        throw FileError(target.string(), "writing", error);
      }
      written += static_cast<size_t>(count);
    }
    if (::close(fd) != 0) throw FileError(target.string(), "writing", errno);
  });
}

namespace {

namespace fs = std::filesystem;

// The folder itself, without a trailing separator or "." (whose name the temporaries take).
fs::path folder_path(const fs::path& target) {
  fs::path path = target.lexically_normal();
  if (path.filename().empty() || path.filename() == "." || path.filename() == "..") {
    path = fs::absolute(target).lexically_normal();
    if (path.filename().empty()) path = path.parent_path();
  }
  return path;
}

// `<name>.<kind>-<pid>-<16 hex digits>` beside `target` (kind "tmp" or "old").
fs::path folder_temporary(const fs::path& target, const char* kind) {
  std::random_device device;
  const uint64_t value = (uint64_t{device()} << 32) ^ uint64_t { device() };
  char digits[17];
  std::snprintf(digits, sizeof digits, "%016" PRIx64, value);
  std::string name = target.filename().string();
  name += '.';
  name += kind;
  name += '-';
  name += std::to_string(::getpid());
  name += '-';
  name += digits;
  return target.parent_path() / name;
}

// The pid in `name` when it is `<prefix><kind>-<pid>-<16 hex digits>`, else 0.
long temporary_pid(const std::string& name, const std::string& prefix, const std::string& kind) {
  const std::string start = prefix + kind + "-";
  if (name.compare(0, start.size(), start) != 0) return 0;
  const size_t dash = name.find('-', start.size());
  if (dash == std::string::npos || dash == start.size() || dash - start.size() > 9 || name.size() != dash + 17)
    return 0;
  for (size_t i = start.size(); i < dash; ++i)
    if (name[i] < '0' || name[i] > '9') return 0;
  for (size_t i = dash + 1; i < name.size(); ++i)
    if (!std::isxdigit(static_cast<unsigned char>(name[i]))) return 0;
  return std::stol(name.substr(start.size(), dash - start.size()));
}

bool process_runs(long pid) { return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM; }

// fsync of every file and folder under `folder`, and of `folder`; a failure names the file as it
// will be under `target`.
void sync_tree(const fs::path& folder, const fs::path& target) {
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (entry.is_symlink()) continue;
    if (entry.is_regular_file()) sync_file(entry.path(), target / entry.path().lexically_relative(folder));
    else if (entry.is_directory()) fsync_directory(entry.path());
  }
  fsync_directory(folder);
}

void remove_quietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove_all(path, ignored);
}

// Moves the finished folder `temporary` onto `target` (see write_folder_atomically).
void move_into_place(const fs::path& temporary, const fs::path& target, bool replace) {
  const fs::path parent = target.parent_path();
  std::error_code error;
  const bool occupied = fs::exists(target) && !fs::is_empty(target);
  if (!occupied || !replace) {
    // rename(2) replaces an empty folder and fails on one with entries: a folder that another
    // process filled since the check is not overwritten.
    fs::rename(temporary, target, error);
    if (error == std::errc::directory_not_empty || error == std::errc::file_exists)
      throw InputError(target.string() + ": already exists; not replaced");
    if (error)
      throw FileError(target.string(), "renaming the new folder " + temporary.filename().string() + " into place",
                      error.value());
    fsync_directory(parent);
    return;
  }
  // One step: `target` holds a complete folder throughout, the old one ends up at `temporary`.
  if (::renameat2(AT_FDCWD, temporary.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
    fsync_directory(parent);
    remove_quietly(temporary);
    fsync_directory(parent);
    return;
  }
  if (errno != EINVAL && errno != ENOSYS && errno != ENOTSUP)
    throw FileError(target.string(), "swapping the new folder " + temporary.filename().string() + " into place", errno);
  // No swap on this file system: the old folder aside (complete), the new one in (complete).
  const fs::path aside = folder_temporary(target, "old");
  fs::rename(target, aside, error);
  if (error)
    throw FileError(target.string(), "renaming the old folder aside to " + aside.filename().string(), error.value());
  fs::rename(temporary, target, error);
  if (error) {
    std::error_code ignored;
    fs::rename(aside, target, ignored);
    throw FileError(target.string(), "renaming the new folder " + temporary.filename().string() + " into place",
                    error.value());
  }
  fsync_directory(parent);
  remove_quietly(aside);
  fsync_directory(parent);
}

}  // namespace

void remove_stale_folder_temporaries(const fs::path& target_given) {
  const fs::path target = folder_path(target_given);
  const fs::path parent = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string prefix = target.filename().string() + ".";
  std::vector<std::pair<fs::path, bool>> stale;  // path, set aside (an old folder)
  std::error_code error;
  for (fs::directory_iterator it(parent, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const long building = temporary_pid(name, prefix, "tmp");
    const long aside = temporary_pid(name, prefix, "old");
    const long pid = building ? building : aside;
    if (pid > 0 && !process_runs(pid)) stale.emplace_back(it->path(), aside > 0);
  }
  if (stale.empty()) return;
  for (const auto& [path, old] : stale) {
    std::error_code ignored;
    if (old && !fs::exists(target)) {  // a killed swap without RENAME_EXCHANGE: the old folder goes back
      fs::rename(path, target, ignored);
      if (!ignored) continue;
    }
    remove_quietly(path);
  }
  fsync_directory(parent);
}

void write_folder_atomically(const fs::path& target_given, bool replace,
                             const std::function<void(const fs::path& temporary)>& write_into) {
  const fs::path target = folder_path(target_given);
  std::error_code error;
  if (!target.parent_path().empty() && !fs::create_directories(target.parent_path(), error) && error)
    throw FileError(target.parent_path().string(), "creating the folder", error.value());
  remove_stale_folder_temporaries(target);
  if (fs::exists(target)) {
    if (!fs::is_directory(target)) throw InputError(target.string() + ": exists and is not a folder");
    if (!replace && !fs::is_empty(target)) throw InputError(target.string() + ": already exists; not replaced");
  }
  const fs::path temporary = folder_temporary(target, "tmp");
  if (!fs::create_directory(temporary, error) && error)
    throw FileError(target.string(), "creating the temporary folder " + temporary.filename().string(), error.value());
  try {
    write_into(temporary);
    sync_tree(temporary, target);
    move_into_place(temporary, target, replace);
  } catch (...) {
    remove_quietly(temporary);
    throw;
  }
}

}  // namespace fovlab
