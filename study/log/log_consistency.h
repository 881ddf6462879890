#pragma once
// The cheap checks of a log against its own header, which export and analyze run on every log
// (replay runs them too, among its differences): the header's study, config_hash and session_seed
// are those of the config_toml it carries, and its complete trials are the schedule that config
// makes for its participant (schedule_check.h), none added, removed or changed, and a session that
// says it completed holds all of them. A log whose chain a forger rebuilt after deleting or adding
// a trial, or after editing its config_hash, still fails these; a log that fails one is broken, at
// the line of the header or of the trial, with the reason in the same words for every reader.
//
// Their cost is reading the config: LoggedConfigs parses each distinct config text once (a study's
// logs all carry the same), for any number of threads; a plan is made per participant.
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "study/config/study_config.h"
#include "study/log/log_integrity.h"
#include "study/log/session_record.h"
#include "study/log/session_scan.h"

namespace fovlab {

// The configs of log headers, each parsed once (without a scene catalog: scene names as written).
class LoggedConfigs {
 public:
  // The config `header` carries (its config_toml and conditions_csv, read by its schema_version),
  // or null with `error` saying why it cannot be read ("PATH (config_toml):LINE: ...").
  std::shared_ptr<const StudyConfig> config_of(const nlohmann::json& header, const std::string& path,
                                               std::string& error);

 private:
  struct Parsed {
    std::shared_ptr<const StudyConfig> config;
    std::string error;  // without the path of the log that first carried it
  };
  std::mutex mutex_;
  std::map<std::tuple<int, std::string, std::string>, Parsed>
      parsed_;  // by schema version, config_toml, conditions_csv
};

// What a header says that its own config contradicts: "study \"A\" but its config_toml names study
// \"B\"", "config_hash H is not the hash of its config_toml (H')", "session_seed differs from the
// one derived from the study seed and participant"; empty when nothing.
std::vector<std::string> header_differences(const nlohmann::json& header, const StudyConfig& config);

struct LogInconsistency {
  int line = 0;        // the header's (1), a trial_start's, or the session_end's
  std::string reason;  // "header: ...", "trial N: ...", "session_end: ..."
};

// The first thing in the log that its header contradicts (the checks above), or none. For either
// reader's trials; `ended_completed`: the log has a session_end whose reason is "completed", at
// `end_line`.
std::optional<LogInconsistency> check_log_against_header(const nlohmann::json& header, const SessionRecord& record,
                                                         const std::string& path, LoggedConfigs& configs);
std::optional<LogInconsistency> check_log_against_header(const nlohmann::json& header, const ScannedSession& session,
                                                         const std::string& path, LoggedConfigs& configs);

// A log's verdict with the checks above: broken at the inconsistency unless it is broken already
// (its chain, a seal or a MAC: that reason comes first).
void mark_inconsistent(LogIntegrity& integrity, const std::optional<LogInconsistency>& inconsistency);

}  // namespace fovlab
