#include "study/log/study_versions.h"

#include <algorithm>
#include <cctype>
#include <exception>

#include "core/input_error.h"
#include "core/session_files.h"
#include "study/log/log_consistency.h"
#include "study/log/session_scan.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

bool is_real_folder(const fs::path& path) {
  std::error_code error;
  return fs::is_directory(fs::symlink_status(path, error));
}

bool has_session_log(const fs::path& results_dir, const std::string& folder, const std::string& participant) {
  std::error_code error;
  return fs::exists(fs::symlink_status(results_dir / folder / participant / kSessionLogName, error));
}

int sessions_of_other_versions(const std::map<std::string, int>& versions, const std::string& content_hash) {
  int others = 0;
  for (const auto& [hash, sessions] : versions)
    if (hash != content_hash) others += sessions;
  return others;
}

}  // namespace

std::string study_version_folder_name(const std::string& study, int version) {
  return version <= 1 ? study : study + "@v" + std::to_string(version);
}

std::optional<int> study_version_of_folder_name(const std::string& study, const std::string& folder_name) {
  if (folder_name == study) return 1;
  const std::string prefix = study + "@v";
  if (!folder_name.starts_with(prefix)) return std::nullopt;
  const std::string digits = folder_name.substr(prefix.size());
  if (digits.empty() || digits.size() > 6 || digits.front() == '0' ||
      !std::all_of(digits.begin(), digits.end(),
                   [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }))
    return std::nullopt;
  const int version = std::stoi(digits);
  return version >= 2 ? std::optional<int>(version) : std::nullopt;
}

std::map<int, std::string> study_version_folders(const fs::path& results_dir, const std::string& study) {
  std::map<int, std::string> folders;
  if (!is_real_folder(results_dir)) return folders;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(results_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (const std::optional<int> version = study_version_of_folder_name(study, name);
        version && is_real_folder(entry.path()))
      folders.emplace(*version, name);
  }
  return folders;
}

std::map<std::string, int> study_folder_versions(const fs::path& study_folder, const std::string& study) {
  std::map<std::string, int> versions;
  if (!is_real_folder(study_folder)) return versions;
  std::vector<fs::path> logs;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(study_folder, error)) {
    if (!is_real_folder(entry.path())) continue;
    const fs::path log = entry.path() / kSessionLogName;
    std::error_code status_error;
    if (fs::is_regular_file(fs::symlink_status(log, status_error))) logs.push_back(log);
  }
  std::sort(logs.begin(), logs.end());
  LoggedConfigs configs;
  for (const fs::path& log : logs) {
    try {
      const ScannedSession session = scan_session_log(log.string());
      if (session.header.value("study", "") != study) continue;
      std::string reason;
      const std::shared_ptr<const StudyConfig> config = configs.config_of(session.header, log.string(), reason);
      if (config) ++versions[config->content_hash];
    } catch (const std::exception&) {
      // An unreadable log tells no version (analyze and export name it and say why).
    }
  }
  return versions;
}

std::string choose_study_folder(const fs::path& results_dir, const StudyConfig& config, const std::string& participant,
                                bool new_version) {
  const std::string& study = config.name;
  const std::map<int, std::string> folders = study_version_folders(results_dir, study);
  // The folder of this config's version: the first whose sessions are all of it, else the next.
  std::string own_folder;
  std::map<std::string, std::map<std::string, int>> versions_of;  // folder -> its versions
  for (const auto& [version, folder] : folders) {
    versions_of[folder] = study_folder_versions(results_dir / folder, study);
    if (own_folder.empty() && sessions_of_other_versions(versions_of[folder], config.content_hash) == 0)
      own_folder = folder;
  }
  if (own_folder.empty())
    own_folder = study_version_folder_name(study, folders.empty() ? 1 : std::max(2, folders.rbegin()->first + 1));

  const std::string base = study_version_folder_name(study, 1);
  std::string chosen;
  if (has_session_log(results_dir, base, participant)) {
    if (!new_version || own_folder == base) return base;  // resumed as before (its log is checked against the config)
  }
  if (new_version) {
    chosen = own_folder;
    if (has_session_log(results_dir, chosen, participant)) return chosen;  // resumed in its version's folder
  } else {
    chosen = base;
    const int others = sessions_of_other_versions(versions_of[base], config.content_hash);
    if (others > 0)
      throw InputError(config.source_path + ": differs from the config " + std::to_string(others) + " session(s) in " +
                       (results_dir / base).string() +
                       " ran (what it says, comments and formatting aside); a new participant would pool two versions "
                       "of the study: restore the config they ran (their logs carry it), or start a new version with "
                       "--new-version (its sessions go to " +
                       (results_dir / own_folder).string() + ")");
  }
  // A new participant: its ID names one person in every version of the study.
  for (const auto& [version, folder] : folders)
    if (folder != chosen && has_session_log(results_dir, folder, participant))
      throw InputError("--participant " + participant + ": already has a session in " +
                       (results_dir / folder / participant).string() + " (another version of study " + study +
                       "); use another participant ID");
  return chosen;
}

}  // namespace fovlab
