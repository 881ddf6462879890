#pragma once
// Whole-file writes that are all-or-nothing: write to a temporary file next to the target, flush,
// then rename over it. A crash leaves the old file (or none), never a torn one.
#include <filesystem>
#include <functional>
#include <string_view>

namespace fovlab {

// Temporary sibling of `target` that keeps its extension (image writers choose the format by it).
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

// Calls `write_to(temporary_path)`, then renames the temporary file onto `target`. On any exception
// the temporary file is removed and the exception propagates.
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write_to);

// fsync of a folder, so the names created or renamed in it survive a power cut (best effort).
void fsync_directory(const std::filesystem::path& directory);

// Convenience for text files (JSON, CSV, Markdown).
void write_text_atomically(const std::filesystem::path& target, std::string_view text);

}  // namespace fovlab
