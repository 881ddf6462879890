#include "core/memory_budget.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/input_error.h"

namespace fovlab {

std::optional<AvailableMemory> available_memory() {
  if (const char* limit = std::getenv(kMemoryLimitVariable)) {
    const std::string text = limit;
    const bool digits = !text.empty() && text.size() <= 19 && text.find_first_not_of("0123456789") == std::string::npos;
    if (!digits)
      throw InputError(std::string(kMemoryLimitVariable) + ": expected a whole number of bytes, got \"" + text + "\"");
    return AvailableMemory{std::stoull(text), kMemoryLimitVariable};
  }
  std::ifstream meminfo("/proc/meminfo");
  std::string line;
  while (std::getline(meminfo, line)) {
    std::istringstream fields(line);
    std::string key, unit;
    uint64_t kib = 0;
    if (fields >> key >> kib >> unit && key == "MemAvailable:" && unit == "kB")
      return AvailableMemory{kib * 1024,
                             std::string("MemAvailable in /proc/meminfo; ") + kMemoryLimitVariable + " overrides"};
  }
  return std::nullopt;
}

std::string memory_text(uint64_t bytes) {
  char text[64];
  if (bytes >= (uint64_t{1} << 30))
    std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / double(uint64_t{1} << 30));
  else if (bytes >= (uint64_t{1} << 20))
    std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(uint64_t{1} << 20));
  else if (bytes >= (uint64_t{1} << 10))
    std::snprintf(text, sizeof text, "%.1f KiB", double(bytes) / double(uint64_t{1} << 10));
  else std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  return text;
}

void check_memory_fits(uint64_t needed_bytes, const std::string& what, const std::string& advice) {
  const std::optional<AvailableMemory> available = available_memory();
  if (!available || needed_bytes <= available->bytes) return;
  throw InputError(what + ": needs about " + memory_text(needed_bytes) + " in memory, more than the " +
                   memory_text(available->bytes) + " available (" + available->source + "); " + advice);
}

}  // namespace fovlab
