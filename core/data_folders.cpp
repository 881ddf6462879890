#include "core/data_folders.h"

#include <array>
#include <cstdlib>
#include <system_error>

namespace fovlab {

std::filesystem::path stimuli_directory() {
  static const std::filesystem::path found = [] {
    std::error_code error;
    const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", error);
    if (!error) {
      const std::filesystem::path dir = program.parent_path();
      const std::array<std::filesystem::path, 4> candidates = {dir / "stimuli", dir / ".." / "stimuli",
                                                               dir / ".." / ".." / "stimuli",
                                                               dir / ".." / "share" / "fovlab" / "stimuli"};
      for (const auto& candidate : candidates)
        if (std::filesystem::is_directory(candidate, error)) return candidate.lexically_normal();
    }
    return std::filesystem::path("stimuli");
  }();
  return found;
}

std::filesystem::path stimuli_subdirectory(const char* variable, const char* sub) {
  if (const char* folder = std::getenv(variable); folder && *folder) return folder;
  return stimuli_directory() / sub;
}

}  // namespace fovlab
