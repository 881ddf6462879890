#pragma once
// A study's config versions on disk. Each version of a study's config (StudyConfig::content_hash:
// what the config says, comments and formatting aside) has its own study folder under the results
// folder: the first version results/<study>, later ones results/<study>@v2, results/<study>@v3, ...
// ('@' is no study name's character, so no other study's folder can be one of these). `fovlab run`
// starts a new participant only in the folder of its config's version, and makes a new version's
// folder only when told (--new-version), so versions never pool silently.
//
// A folder's versions are read from its sessions' log headers through the bounded fast scan
// (session_scan.h) and LoggedConfigs (log_consistency.h); nothing is written, so the participant
// folders' owners (docs/reliability.md) are never disturbed.
#include <filesystem>
#include <map>
#include <optional>
#include <string>

#include "study/config/study_config.h"

namespace fovlab {

// "<study>" for version 1, "<study>@v<N>" for N >= 2.
std::string study_version_folder_name(const std::string& study, int version);
// The version a folder name is of `study` (1 for "<study>", N for "<study>@vN"), or none.
std::optional<int> study_version_of_folder_name(const std::string& study, const std::string& folder_name);

// The config versions of the sessions in one study folder: content hash -> sessions. Every
// participant folder's events.jsonl is scanned; a log that cannot be read, whose config_toml cannot
// be parsed, or that belongs to another study tells no version and is not counted. A missing
// folder has none.
std::map<std::string, int> study_folder_versions(const std::filesystem::path& study_folder, const std::string& study);

// Where a participant's session of `config` goes: the name of its study folder under results_dir.
// An existing participant (a folder with a log in results/<study>, or, with new_version, in the
// folder of the config's version) resumes there as before. A new participant runs in
// results/<study> when the sessions there are of the config's version (or there are none);
// otherwise InputError (exit 2) naming the config, the folder, how many sessions used another
// version and what to do, unless new_version: then the folder of its version, results/<study>@vN
// (the first whose sessions are all of it, else the next unused N).
std::string choose_study_folder(const std::filesystem::path& results_dir, const StudyConfig& config,
                                const std::string& participant, bool new_version);

// Every version folder of `study` under results_dir ("<study>", "<study>@v2", ...), by version.
std::map<int, std::string> study_version_folders(const std::filesystem::path& results_dir, const std::string& study);

}  // namespace fovlab
