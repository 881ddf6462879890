#pragma once
// The one check of every path a command writes, whether the user named it (--out, --json,
// --out-dir, --cache, ...) or it is the command's default (export's trials.csv, analyze's folder,
// the caches). It runs before any work, and refuses (InputError, one line, exit 2) a target that
// is, or resolves through symbolic links to:
// - a file a session owns, wherever it lies (core/session_files.h: events.jsonl, session.lock,
//   events.jsonl.* set aside beside a log): no flag, --force included, lifts this;
// - anything inside a participant's folder (one holding a session log or lock), at any depth: only
//   the session that owns the folder writes there, except the files a command names in
//   `owned_names_in_participant_folder` (export's trials.csv and steps.csv beside the log it reads);
// - for a file: a folder, something that is not a regular file (a device, a FIFO: a rename would
//   replace /dev/null itself), a missing or unwritable folder to put it in; for an image, an
//   extension OpenImageIO cannot write; for a folder: an existing file.
// Whether an existing file outside participant folders is replaced is each command's own rule,
// stated in its --help (app/output_options.h). Writers then write atomically (core/atomic_file.h).
#include <filesystem>
#include <string>
#include <vector>

namespace fovlab {

enum class OutputKind {
  file,        // one file (JSON, CSV, SVG, Markdown)
  image_file,  // one image, its format from its extension
  folder,      // a folder the command writes files into (made when missing)
};

struct OutputTarget {
  OutputKind kind = OutputKind::file;
  // File names this command writes into a participant's folder by its documented default.
  std::vector<std::string> owned_names_in_participant_folder;
};

// Throws InputError "FLAG PATH: WHY; expected ..." (no "FLAG " when `flag` is empty: a default
// path) when this command must not write `path`.
void check_output_target(const std::filesystem::path& path, const std::string& flag, const OutputTarget& target);

// The same check as a message: empty when `path` may be written (the command line's validators).
std::string output_target_refusal(const std::filesystem::path& path, const std::string& flag,
                                  const OutputTarget& target);

// check_output_target as a folder, then makes it and its parents when missing (FileError with the
// system's reason when that fails).
void create_output_folder(const std::filesystem::path& folder, const std::string& flag);

// `path` with the symbolic links of the folders above it and of its own name followed (a
// dangling link's target is where a write would land), absolute and normalised.
std::filesystem::path resolved_output_path(const std::filesystem::path& path);

}  // namespace fovlab
