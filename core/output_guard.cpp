#include "core/output_guard.h"

#include <unistd.h>

#include <algorithm>

#include "core/image_io.h"
#include "core/input_error.h"
#include "core/session_files.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

// The path as given, absolute and normalised, without a trailing separator.
fs::path lexical_path(const fs::path& path) {
  fs::path normal = fs::absolute(path).lexically_normal();
  if (normal.filename().empty() && normal.has_parent_path()) normal = normal.parent_path();
  return normal;
}

std::string what_session_file(const std::string& name) {
  if (name == kSessionLogName) return "a session's log (" + name + ")";
  if (name == kSessionLockName) return "a session's lock (" + name + ")";
  return "a file a session set aside beside its log (" + name + ")";
}

std::string file_type_text(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::character:
      return "a character device";
    case fs::file_type::block:
      return "a block device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

// Why `path` (lexical or resolved) may not be written, or "".
std::string session_refusal(const fs::path& path, const OutputTarget& target) {
  const std::string name = path.filename().string();
  if (is_session_file_name(name)) return what_session_file(name);
  if (target.kind == OutputKind::folder)
    if (const std::string mark = participant_folder_mark(path); !mark.empty())
      return "a participant's folder (it holds " + std::string(mark) + ")";
  for (fs::path folder = path.parent_path();; folder = folder.parent_path()) {
    if (const std::string mark = participant_folder_mark(folder); !mark.empty()) {
      const auto& owned = target.owned_names_in_participant_folder;
      const bool owned_here = target.kind != OutputKind::folder && folder == path.parent_path() &&
                              std::find(owned.begin(), owned.end(), name) != owned.end();
      if (!owned_here) return "inside the participant's folder " + folder.string() + " (it holds " + mark + ")";
    }
    if (!folder.has_parent_path() || folder == folder.parent_path()) break;
  }
  return "";
}

}  // namespace

fs::path resolved_output_path(const fs::path& path) {
  // Resolved as the kernel does, each link before a ".." that follows it (l/../x, with l a link,
  // is the folder beside l's target, not beside l): never normalised as text first.
  fs::path current = fs::absolute(path);
  if (current.filename().empty() && current.has_parent_path()) current = current.parent_path();
  for (int hops = 0; hops < 40; ++hops) {  // the kernel's own limit on a chain of links
    std::error_code error;
    if (current.filename() == "." || current.filename() == "..") break;
    if (!fs::is_symlink(fs::symlink_status(current, error))) break;
    const fs::path link = fs::read_symlink(current, error);
    if (error) break;
    current = link.is_absolute() ? link : current.parent_path() / link;
  }
  std::error_code error;
  if (current.filename() == "." || current.filename() == "..") {
    const fs::path folder = fs::weakly_canonical(current, error);
    return error ? current.lexically_normal() : folder;
  }
  const fs::path folder = fs::weakly_canonical(current.parent_path(), error);
  return error ? current.lexically_normal() : folder / current.filename();
}

std::string output_target_refusal(const fs::path& path, const std::string& flag, const OutputTarget& target) {
  const std::string named = flag.empty() ? path.string() : flag + " " + path.string();
  const std::string expected = target.kind == OutputKind::folder ? "expected a folder outside participant folders"
                                                                 : "expected a path outside participant folders";
  if (path.empty()) return (flag.empty() ? std::string("an output path") : flag) + ": empty; expected a path";
  const fs::path lexical = lexical_path(path);
  const fs::path resolved = resolved_output_path(path);
  if (std::string why = session_refusal(lexical, target); !why.empty())
    return named + ": " + why + "; only that participant's session writes there: " + expected;
  if (resolved != lexical)
    if (std::string why = session_refusal(resolved, target); !why.empty())
      return named + ": resolves to " + resolved.string() + ", " + why +
             "; only that participant's session writes there: " + expected;

  std::error_code error;
  const fs::file_status status = fs::status(path, error);  // through links: what a write would meet
  if (target.kind == OutputKind::folder) {
    if (fs::exists(status) && !fs::is_directory(status))
      return named + ": " + (fs::is_regular_file(status) ? std::string("a file") : file_type_text(status.type())) +
             "; expected a folder";
    // Made when missing: the nearest folder that exists must take new entries.
    fs::path existing = lexical;
    while (!fs::exists(existing, error) && existing.has_parent_path() && existing != existing.parent_path())
      existing = existing.parent_path();
    if (!fs::is_directory(existing, error))
      return named + ": cannot be made (" + existing.string() + " is not a folder); expected a folder";
    if (::access(existing.c_str(), W_OK) != 0) return named + ": folder " + existing.string() + " is not writable";
    return "";
  }
  if (fs::exists(status) && !fs::is_regular_file(status))
    return named + ": " + file_type_text(status.type()) + "; expected a regular file or a new file's path";
  const fs::path folder = lexical.parent_path();
  if (!fs::is_directory(folder, error)) return named + ": folder " + folder.string() + " does not exist";
  if (::access(folder.c_str(), W_OK) != 0) return named + ": folder " + folder.string() + " is not writable";
  if (target.kind == OutputKind::image_file && !can_encode_image(path))
    return named + ": unknown image format; expected a .png, .exr or other extension OpenImageIO writes";
  return "";
}

void check_output_target(const fs::path& path, const std::string& flag, const OutputTarget& target) {
  if (std::string refusal = output_target_refusal(path, flag, target); !refusal.empty()) throw InputError(refusal);
}

void create_output_folder(const fs::path& folder, const std::string& flag) {
  check_output_target(folder, flag, {OutputKind::folder});
  std::error_code error;
  fs::create_directories(folder, error);
  if (error)
    throw FileError(folder.string(), "creating the folder" + (flag.empty() ? std::string() : " of " + flag),
                    error.value());
}

}  // namespace fovlab
