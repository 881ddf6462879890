#pragma once
// Reading a file the user named (a study config, a gaze trace, a mesh, a scene), guarded:
// - only a regular file (or a link to one): a directory, a device such as /dev/zero, a FIFO or a
//   socket is refused before a byte is read (a FIFO is opened without blocking, so a missing writer
//   cannot hang the command);
// - at most `max_bytes`: a larger file is refused from its size at once, and a file that grows while
//   it is read is refused after max_bytes + 1 bytes, so no more than that is ever read.
// Errors are one-line InputErrors that start with the path and end with what was expected, e.g.
//   "dir: not a regular file (a directory): expected a study config (.toml)"
//   "big.toml: larger than 16 MiB (17825792 bytes): expected a study config (.toml) of at most 16 MiB"
// Linux/POSIX (open, fstat, read), like the rest of the project.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>

#include "core/input_error.h"

namespace fovlab {

constexpr std::uint64_t kMebibyte = std::uint64_t(1) << 20;

// "16 MiB" for whole mebibytes, else "N bytes".
inline std::string byte_size_text(std::uint64_t bytes) {
  if (bytes >= kMebibyte && bytes % kMebibyte == 0) return std::to_string(bytes / kMebibyte) + " MiB";
  return std::to_string(bytes) + " bytes";
}

// "NAME: larger than CAP (SIZE): expected WHAT of at most CAP".
[[noreturn]] inline void throw_too_large(const std::string& name, const std::string& expected, std::uint64_t max_bytes,
                                         const std::string& size) {
  throw InputError(name + ": larger than " + byte_size_text(max_bytes) + " (" + size + "): expected " + expected +
                   " of at most " + byte_size_text(max_bytes));
}

// The checks on a file open as `fd` before a byte of it is read: a regular file of at most
// `max_bytes`. Returns its size (a file may still grow while it is read; readers cap what they read
// at max_bytes + 1). `expected` names what the file should be, with its article: "a study config
// (.toml)". Throws the one-line InputErrors above.
inline std::uint64_t check_input_file(int fd, const std::string& name, const std::string& expected,
                                      std::uint64_t max_bytes) {
  const auto fail = [&](const std::string& what) -> void { throw InputError(name + ": " + what + ": expected " + expected); };
  struct stat status {};
  if (::fstat(fd, &status) != 0) fail(std::string("cannot read (") + std::strerror(errno) + ")");
  if (!S_ISREG(status.st_mode)) {
    const char* kind = S_ISDIR(status.st_mode)    ? "a directory"
                       : S_ISCHR(status.st_mode)  ? "a character device"
                       : S_ISBLK(status.st_mode)  ? "a block device"
                       : S_ISFIFO(status.st_mode) ? "a FIFO or pipe"
                       : S_ISSOCK(status.st_mode) ? "a socket"
                                                  : "not a plain file";
    fail(std::string("not a regular file (") + kind + ")");
  }
  if (status.st_size > 0 && std::uint64_t(status.st_size) > max_bytes)
    throw_too_large(name, expected, max_bytes, std::to_string(status.st_size) + " bytes");
  return status.st_size > 0 ? std::uint64_t(status.st_size) : 0;
}

inline std::string read_input_file(const std::filesystem::path& path, const std::string& expected,
                                   std::uint64_t max_bytes) {
  const std::string name = path.string();
  const auto fail = [&](const std::string& what) -> void { throw InputError(name + ": " + what + ": expected " + expected); };
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) fail(std::string("cannot open (") + std::strerror(errno) + ")");
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  const std::uint64_t size = check_input_file(fd, name, expected, max_bytes);

  std::string bytes;
  bytes.reserve(static_cast<size_t>(size));
  char buffer[1 << 16];
  for (;;) {
    // Never more than max_bytes + 1 in all: one byte past the cap is enough to know it is exceeded.
    const std::uint64_t room = max_bytes + 1 - bytes.size();
    const ssize_t count = ::read(fd, buffer, static_cast<size_t>(std::min<std::uint64_t>(sizeof buffer, room)));
    if (count < 0) {
      if (errno == EINTR) continue;
      fail(std::string("cannot read (") + std::strerror(errno) + ")");
    }
    if (count == 0) break;
    bytes.append(buffer, static_cast<size_t>(count));
    if (bytes.size() > max_bytes) throw_too_large(name, expected, max_bytes, "it grew while it was read");
  }
  return bytes;
}

}  // namespace fovlab
