#pragma once
// A small disk for the tests of a full one: a tmpfs mounted at a folder (root only; elsewhere
// mounted() is false and reason() says why, for GTEST_SKIP), unmounted when it goes. fill() takes
// its last free byte.
#include <sys/mount.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace fovlab::testing {

class SmallDisk {
 public:
  explicit SmallDisk(const std::filesystem::path& at) : at_(at) {
    std::filesystem::create_directories(at);
    mounted_ = ::mount("tmpfs", at.c_str(), "tmpfs", 0, "size=64k") == 0;
    if (!mounted_) reason_ = std::strerror(errno);
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(at_.c_str(), MNT_DETACH);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;

  bool mounted() const { return mounted_; }
  const std::string& reason() const { return reason_; }
  bool resize(uintmax_t bytes) {
    const std::string options = "size=" + std::to_string(bytes);
    return ::mount("tmpfs", at_.c_str(), "tmpfs", MS_REMOUNT, options.c_str()) == 0;
  }
  // Writes `file` (in the disk) until the disk is full.
  void fill(const std::filesystem::path& file) const {
    std::ofstream filler(file, std::ios::binary);
    const std::string block(4096, 'x');
    while (filler.write(block.data(), static_cast<std::streamsize>(block.size()))) filler.flush();
  }

 private:
  std::filesystem::path at_;
  bool mounted_ = false;
  std::string reason_;
};

}  // namespace fovlab::testing
