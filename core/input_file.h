#pragma once
// Reading a file the user named (a study config, a gaze trace, a mesh, a scene), guarded:
// - only a regular file (or a link to one): a directory, a device such as /dev/zero, a FIFO or a
//   socket is refused before a byte is read (a FIFO is opened without blocking, so a missing writer
//   cannot hang the command);
// - at most `max_bytes`: a larger file is refused from its size at once, and a file that grows while
//   it is read is refused after max_bytes + 1 bytes, so no more than that is ever read.
// Readers of caches use read_file_if_regular (the same guard; a file that fails it is not used), and
// readers that hand the file to a C library open it as an OpenInputFile and pass its descriptor on, so
// the library never opens a path itself.
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
#include <optional>
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
  const auto fail = [&](const std::string& what) -> void {
    throw InputError(name + ": " + what + ": expected " + expected);
  };
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

// An input file open for reading, checked by check_input_file; closes its descriptor when it goes.
// For readers that hand the open file on (a FILE* for a C library) instead of reading it whole.
class OpenInputFile {
 public:
  OpenInputFile(const std::filesystem::path& path, const std::string& expected, std::uint64_t max_bytes)
      : name_(path.string()) {
    fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);  // a FIFO without a writer must not block
    if (fd_ < 0) throw InputError(name_ + ": cannot open (" + std::strerror(errno) + "): expected " + expected);
    try {
      size_bytes_ = check_input_file(fd_, name_, expected, max_bytes);
    } catch (...) {
      ::close(fd_);
      throw;
    }
  }
  ~OpenInputFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  OpenInputFile(const OpenInputFile&) = delete;
  OpenInputFile& operator=(const OpenInputFile&) = delete;

  int fd() const { return fd_; }
  // Its size when it was checked.
  std::uint64_t size_bytes() const { return size_bytes_; }
  const std::string& name() const { return name_; }

 private:
  std::string name_;
  int fd_ = -1;
  std::uint64_t size_bytes_ = 0;
};

// The rest of an open input file, never more than max_bytes + 1 bytes read (one byte past the cap is
// enough to know it is exceeded: a file that grew after its check).
inline std::string read_open_input_file(const OpenInputFile& file, const std::string& expected,
                                        std::uint64_t max_bytes) {
  std::string bytes;
  bytes.reserve(static_cast<size_t>(std::min(file.size_bytes(), max_bytes)));
  char buffer[1 << 16];
  for (;;) {
    const std::uint64_t room = max_bytes + 1 - bytes.size();
    const ssize_t count = ::read(file.fd(), buffer, static_cast<size_t>(std::min<std::uint64_t>(sizeof buffer, room)));
    if (count < 0) {
      if (errno == EINTR) continue;
      throw InputError(file.name() + ": cannot read (" + std::strerror(errno) + "): expected " + expected);
    }
    if (count == 0) break;
    bytes.append(buffer, static_cast<size_t>(count));
    if (bytes.size() > max_bytes) throw_too_large(file.name(), expected, max_bytes, "it grew while it was read");
  }
  return bytes;
}

inline std::string read_input_file(const std::filesystem::path& path, const std::string& expected,
                                   std::uint64_t max_bytes) {
  const OpenInputFile file(path, expected, max_bytes);
  return read_open_input_file(file, expected, max_bytes);
}

// A file whose absence or oddity is no error (a cache, which is made again rather than trusted to be
// a file): its bytes when it is a regular file of at most `max_bytes` that reads in full, else none.
// The same guard as read_input_file: a FIFO or device is never read, a larger file never past its cap.
inline std::optional<std::string> read_file_if_regular(const std::filesystem::path& path, std::uint64_t max_bytes) {
  try {
    return read_input_file(path, "a regular file", max_bytes);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

}  // namespace fovlab
