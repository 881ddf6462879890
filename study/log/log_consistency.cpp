#include "study/log/log_consistency.h"

#include "core/input_error.h"
#include "study/log/event_log.h"
#include "study/log/log_events.h"
#include "study/log/schedule_check.h"
#include "study/schedule/study_plan.h"

namespace fovlab {
namespace {

namespace k = log_keys;

std::string header_text(const nlohmann::json& header, const char* key) {
  const auto found = header.find(key);
  return found != header.end() && found->is_string() ? found->get<std::string>() : std::string();
}

template <typename Log>
std::optional<LogInconsistency> check(const nlohmann::json& header, const Log& log, bool ended_completed, int end_line,
                                      const std::string& path, LoggedConfigs& configs) {
  std::string error;
  const std::shared_ptr<const StudyConfig> config = configs.config_of(header, path, error);
  if (!config) return LogInconsistency{1, "header: its config_toml cannot be read (" + error + ")"};
  if (const std::vector<std::string> differences = header_differences(header, *config); !differences.empty())
    return LogInconsistency{1, "header: " + differences.front()};
  std::optional<StudyPlan> plan;
  try {
    plan = make_study_plan(*config, header_text(header, k::participant));
  } catch (const InputError& failure) {
    return LogInconsistency{1, std::string("header: its config_toml makes no schedule (") + failure.what() + ")"};
  }
  const ScheduleCheck schedule = check_log_against_schedule(log, *plan, /*keep_presented=*/false);
  if (!schedule.differences.empty())
    return LogInconsistency{schedule.difference_lines.front(), schedule.differences.front()};
  if (ended_completed && !schedule.schedule_done)
    return LogInconsistency{end_line, "session_end: the session says it completed, but the log holds " +
                                          std::to_string(schedule.trials_checked) + " of " +
                                          std::to_string(plan->trials.size()) + " trials and the schedule runs more"};
  return std::nullopt;
}

}  // namespace

std::shared_ptr<const StudyConfig> LoggedConfigs::config_of(const nlohmann::json& header, const std::string& path,
                                                            std::string& error) {
  const int schema_version = header_schema_version(header);
  auto key =
      std::make_tuple(schema_version, header_text(header, k::config_toml), header_text(header, k::conditions_csv));
  const std::string name = path + " (config_toml)";
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (const auto found = parsed_.find(key); found != parsed_.end()) {
      error = found->second.error.empty() ? std::string() : name + found->second.error;
      return found->second.config;
    }
  }
  // Parsed outside the lock (another thread may parse the same text meanwhile: the first kept).
  Parsed parsed;
  try {
    parsed.config = std::make_shared<const StudyConfig>(
        parse_logged_study_config(std::get<1>(key), name, schema_version, nullptr, std::get<2>(key)));
  } catch (const InputError& failure) {
    parsed.error = failure.what();
    if (parsed.error.rfind(name, 0) == 0) parsed.error = parsed.error.substr(name.size());
    else parsed.error = ": " + parsed.error;
  }
  error = parsed.error.empty() ? std::string() : name + parsed.error;
  const std::lock_guard<std::mutex> lock(mutex_);
  return parsed_.emplace(std::move(key), std::move(parsed)).first->second.config;
}

std::vector<std::string> header_differences(const nlohmann::json& header, const StudyConfig& config) {
  std::vector<std::string> differences;
  const std::string study = header_text(header, k::study);
  if (study != config.name)
    differences.push_back("study \"" + study + "\" but its config_toml names study \"" + config.name + "\"");
  const std::string config_hash = header_text(header, k::config_hash);
  if (config_hash != config.hash)
    differences.push_back("config_hash " + config_hash + " is not the hash of its config_toml (" + config.hash + ")");
  const auto seed = header.find(k::session_seed);
  if (seed == header.end() || !seed->is_number_integer() || (!seed->is_number_unsigned() && seed->get<int64_t>() < 0) ||
      seed->get<uint64_t>() != session_seed(config.seed, header_text(header, k::participant)))
    differences.push_back("session_seed differs from the one derived from the study seed and participant");
  return differences;
}

std::optional<LogInconsistency> check_log_against_header(const nlohmann::json& header, const SessionRecord& record,
                                                         const std::string& path, LoggedConfigs& configs) {
  return check(header, record, record.ended && record.end_reason == SessionEndEvent::completed, record.end_line, path,
               configs);
}

std::optional<LogInconsistency> check_log_against_header(const nlohmann::json& header, const ScannedSession& session,
                                                         const std::string& path, LoggedConfigs& configs) {
  return check(header, session.trials, session.ended && session.end_reason == SessionEndEvent::completed,
               session.end_line, path, configs);
}

void mark_inconsistent(LogIntegrity& integrity, const std::optional<LogInconsistency>& inconsistency) {
  if (!inconsistency || integrity.status == LogStatus::broken) return;
  integrity.status = LogStatus::broken;
  integrity.line = inconsistency->line;
  integrity.reason = inconsistency->reason;
}

}  // namespace fovlab
