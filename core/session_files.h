#pragma once
// The files a session owns in its participant's folder, results/<study>/<participant>/: its log, its
// lock, and what it set aside beside the log (a torn last line, its events copied out of a log that
// was replaced under it, the file found at the log's path when it resumed from that copy). Named
// here, in core, so that the session that writes them (study/log, protocols/session) and the output
// guard that keeps every other command away from them (core/output_guard.h) use one list.
#include <filesystem>
#include <string>
#include <string_view>

namespace fovlab {

inline constexpr std::string_view kSessionLogName = "events.jsonl";
inline constexpr std::string_view kSessionLockName = "session.lock";

// What a session sets aside beside its log: "events.jsonl.<kind>-<N>", N = 1, 2, ...
enum class SetAside {
  torn,       // a last line a crash cut short (the log is cut back to its last complete line)
  recovered,  // every event a session wrote, copied from its open log after the log's name was given to another file
  replaced,   // the file a resumed session found at the log's path, kept when it resumed from its recovered copy
};
inline std::string_view set_aside_kind_name(SetAside kind) {
  switch (kind) {
    case SetAside::torn:
      return "torn";
    case SetAside::recovered:
      return "recovered";
    case SetAside::replaced:
      return "replaced";
  }
  return "?";
}
// "events.jsonl.<kind>-": how every such file's name starts.
inline std::string set_aside_name_prefix(const std::filesystem::path& log, SetAside kind) {
  std::string name = log.filename().string();
  name += '.';
  name += set_aside_kind_name(kind);
  name += '-';
  return name;
}
inline std::filesystem::path set_aside_path(const std::filesystem::path& log, SetAside kind, int number) {
  return log.parent_path() / (set_aside_name_prefix(log, kind) + std::to_string(number));
}

// Whether a file of this name belongs to a session wherever it is: the log, the lock, or anything
// set aside beside a log ("events.jsonl.*").
inline bool is_session_file_name(std::string_view name) {
  return name == kSessionLogName || name == kSessionLockName ||
         (name.size() > kSessionLogName.size() && name.starts_with(kSessionLogName) &&
          name[kSessionLogName.size()] == '.');
}

// A participant's folder: one that holds a session log, a session lock (a run takes the lock before
// it writes the first event) or anything a session set aside (a folder left with only
// events.jsonl.recovered-1, after a log was removed under its session, is still a participant's).
// Returns the name of the file that makes it one, "" for any other folder. Symbolic links are
// looked at, not followed.
inline std::string participant_folder_mark(const std::filesystem::path& folder) {
  std::error_code error;
  for (const std::string_view name : {kSessionLogName, kSessionLockName})
    if (std::filesystem::exists(std::filesystem::symlink_status(folder / name, error))) return std::string(name);
  for (std::filesystem::directory_iterator entry(folder, error), end; !error && entry != end; entry.increment(error))
    if (const std::string name = entry->path().filename().string(); is_session_file_name(name)) return name;
  return "";
}

}  // namespace fovlab
