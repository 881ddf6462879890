#pragma once
// Whole-file writes that are all-or-nothing: write to a temporary file next to the target, flush,
// then rename over it. A crash leaves the old file (or none), never a torn one. The same for a
// whole folder of files (write_folder_atomically).
#include <filesystem>
#include <functional>
#include <string_view>

namespace fovlab {

// Temporary sibling of `target` that keeps its extension (image writers choose the format by it):
// ".<stem>.tmp-<host>-<pid><extension>", apart for every process of every machine.
std::filesystem::path temporary_sibling(const std::filesystem::path& target);

// Calls `write_to(temporary_path)`, fsyncs the file, then renames it onto `target`. On any exception
// the temporary file is removed and the exception propagates. A failed fsync or rename is a
// FileError naming `target`, the operation and the system's reason ("No space left on device").
void write_atomically(const std::filesystem::path& target,
                      const std::function<void(const std::filesystem::path&)>& write_to);

// fsync of a folder, so the names created or renamed in it survive a power cut (best effort).
void fsync_directory(const std::filesystem::path& directory);

// Convenience for text files (JSON, CSV, Markdown): written with write(2), so a failure is a
// FileError with the system's reason ("PATH: writing failed (No space left on device)").
void write_text_atomically(const std::filesystem::path& target, std::string_view text);

// Whole-folder writes, for a set of files that belong together (fovlab analyze's outputs): the
// files are written into a temporary sibling folder, `<name>.tmp-<pid>-<16 hex digits>`, every file
// and the folder are fsync'd, then the folder is renamed onto `target` in one step. A kill leaves
// the old folder (or none) or the new one at `target`, never a mix.
//
// `replace` false: `target` must be absent or an empty folder, else InputError naming it (nothing
// is written). `replace` true: an existing `target` is swapped with the new folder in one step
// (renameat2 RENAME_EXCHANGE), so `target` holds a complete folder at every instant, and the old
// one is then removed. Where the file system cannot swap, the old folder is renamed aside
// (`<name>.old-<pid>-<hex>`) and the new one renamed in: a kill between the two leaves both
// complete beside `target`, and the next call puts the old one back first.
//
// Every call first removes the temporaries that killed calls left beside `target` (names of the
// patterns above whose process no longer runs). On an exception from `write_into` the temporary
// folder is removed and the exception propagates; `target` is untouched. A folder the system does not
// let it make, a file it cannot fsync or a rename it refuses is a FileError with the system's reason.
void write_folder_atomically(const std::filesystem::path& target, bool replace,
                             const std::function<void(const std::filesystem::path& temporary)>& write_into);

// The cleanup write_folder_atomically starts with (exposed for tests and callers that check
// `target` before writing): removes `<name>.tmp-<pid>-<hex>` and puts back or removes
// `<name>.old-<pid>-<hex>` folders beside `target` whose process is gone. Best effort.
void remove_stale_folder_temporaries(const std::filesystem::path& target);

}  // namespace fovlab
