#pragma once
// The whole content of a file, or nullopt when it cannot be opened or read (errno then says why).
// Callers word their own message (which file it was meant to be, what was expected).
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

namespace fovlab {

inline std::optional<std::string> read_file_bytes(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return std::nullopt;
  std::ostringstream bytes;
  bytes << file.rdbuf();
  if (file.bad()) return std::nullopt;
  return bytes.str();
}

}  // namespace fovlab
