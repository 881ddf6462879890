#pragma once
// Work that would not fit in memory is refused before it starts, with one line naming what drives
// its size, instead of running for minutes and dying of std::bad_alloc (issue 14).
#include <cstdint>
#include <optional>
#include <string>

namespace fovlab {

// Set to a whole number of bytes, it replaces MemAvailable as the memory available (tests, and a
// machine shared with other work).
inline constexpr const char* kMemoryLimitVariable = "FOVLAB_MEMORY_LIMIT_BYTES";

struct AvailableMemory {
  uint64_t bytes = 0;
  std::string source;  // where the figure comes from, for messages
};

// FOVLAB_MEMORY_LIMIT_BYTES when set (anything but a whole number of bytes is an InputError naming
// it), else MemAvailable of /proc/meminfo; none when neither can be read (nothing is refused then).
std::optional<AvailableMemory> available_memory();

// "34.0 GiB", "512.0 MiB", "90.0 KiB", "900 bytes".
std::string memory_text(uint64_t bytes);

// InputError "<what>: needs about N in memory, more than the M available (source); <advice>" when
// `needed_bytes` exceeds the memory available.
void check_memory_fits(uint64_t needed_bytes, const std::string& what, const std::string& advice);

}  // namespace fovlab
