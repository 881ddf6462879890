#include "protocols/session/trials_export.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include "core/csv.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "study/config/study_config.h"
#include "study/protocol/protocol_rules.h"
#include "study/log/log_consistency.h"
#include "study/log/session_copies.h"
#include "study/log/session_record.h"
#include "study/schedule/study_plan.h"

namespace fovlab {
namespace {

std::string number_cell(const nlohmann::json& value) {
  if (value.is_null()) return "";
  if (value.is_number_integer()) return std::to_string(value.get<int64_t>());
  if (value.is_number()) return format_number(value.get<double>(), 10);
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  return value.is_string() ? value.get<std::string>() : value.dump();
}

template <typename T>
nlohmann::json optional_json(const std::optional<T>& value) {
  return value ? nlohmann::json(*value) : nlohmann::json();
}

const char* const columns[] = {
    "study", "participant", "observer", "protocol", "trial", "block", "block_name", "scene", "condition", "variant",
    "level", "attention_check", "reference_first", "ramp_toward_reference", "answer", "answers", "rt_s", "saved_level",
    "attention_correct", "onset_s", "end_s", "dropped_frames", "excluded", "log_status",
    // Issue 18: what PsychoPy users look for in a trials file.
    "key", "correct", "repeat", "level_parameter", "session_started_utc", "fovlab_version", "config_hash", "refresh_hz",
    // [practice] trials: exported, never analysed.
    "practice",
    // An adaptive trial's track (as adaptive_tracks.csv names it); empty otherwise.
    "track", "track_procedure", "track_kind",
    // The session's gaze source kind (several runs, several kinds: "tracker+mouse").
    "gaze_source"};
// After the [participant] fields' columns, so that no earlier column moves: a headset trial's
// refreshes ended after their predicted display time (its stimulus events' late_frames, summed);
// empty where the session did not measure them (a desktop session, a runtime without
// XR_KHR_convert_timespec_time).
const char* const last_columns[] = {"late_frames"};

const char* const step_columns[] = {"study", "participant", "observer",       "protocol", "trial",
                                    "step",  "level",       "previous_level", "answer",   "key",
                                    "rt_s",  "correct",     "log_status",     "practice"};

// The level of stimulus `id` in the header's stimuli (null for the reference or an unknown id).
nlohmann::json stimulus_level(const nlohmann::json& header, int id) {
  const auto stimuli = header.find("stimuli");
  if (stimuli == header.end() || !stimuli->is_array() || id < 0 || size_t(id) >= stimuli->size()) return nullptr;
  const nlohmann::json& stimulus = (*stimuli)[size_t(id)];
  if (!stimulus.is_object() || stimulus.value("is_reference", false)) return nullptr;
  const auto level = stimulus.find("level");
  return level != stimulus.end() && level->is_number() ? *level : nlohmann::json();
}

// The config's level parameter, from the config text the header carries ("" when it has none or
// the text cannot be read).
std::string level_parameter(const nlohmann::json& header, const std::string& path, LoggedConfigs& configs) {
  std::string error;
  const std::shared_ptr<const StudyConfig> config = configs.config_of(header, path, error);
  return config ? config->levels.parameter : std::string();
}

// An adaptive trial's track by its index as logged: its [procedure.NAME] name and its kind
// ("staircase" or "quest_plus"), from the schedule the header's config makes for its participant
// (made only for a log with adaptive trials; none when the config cannot be read).
struct TrackNames {
  std::string procedure, kind;
};
std::vector<TrackNames> track_names(const nlohmann::json& header, const SessionRecord& record, const std::string& path,
                                    LoggedConfigs& configs) {
  if (std::none_of(record.trials.begin(), record.trials.end(),
                   [](const RecordedTrial& trial) { return trial.start.track.has_value(); }))
    return {};
  std::string error;
  const std::shared_ptr<const StudyConfig> config = configs.config_of(header, path, error);
  if (!config) return {};
  std::vector<TrackNames> names;
  try {
    for (const AdaptiveTrack& track : make_study_plan(*config, header.value("participant", "")).tracks)
      names.push_back({config->procedures.at(static_cast<size_t>(track.procedure)).name,
                       track.kind == ProcedureConfig::Kind::staircase ? "staircase" : "quest_plus"});
  } catch (const InputError&) {
    return {};  // a config that makes no schedule: the log is broken already (log_consistency.h)
  }
  return names;
}

}  // namespace

namespace {

// The export; `current` names the log being read, for the caller's message.
ExportedCsv export_checked(const std::vector<std::string>& log_paths, const ExportOptions& options,
                           std::string& current) {
  // The config's [participant] fields, one column each ("field_age"), over every log.
  // Every log is read once, first, so the field columns are known before the first row.
  std::set<std::string> field_names;
  std::vector<SessionRecord> records;
  std::vector<size_t> torn_bytes;  // of each log's cut-off last line (0: none)
  std::vector<SessionLogIdentity> identities;
  for (const std::string& path : log_paths) {
    current = path;
    const EventLogFile log = read_event_log(path);
    torn_bytes.push_back(log.torn_tail ? log.torn_tail->size() : 0);
    records.push_back(read_session_record(log, options.lab_key));
    identities.push_back({path, log.header_chain, records.back().header.value("participant", ""),
                          static_cast<int>(log.events.size()), log.first_chain_error_line});
  }
  // One session counted once: a copy of another log of its session is left out; two logs of one
  // session that part are both broken (session_copies.h).
  std::vector<bool> copy(log_paths.size(), false);
  for (const SessionCopy& found : find_session_copies(identities)) {
    if (found.kind == SessionCopy::Kind::copy) {
      copy[found.log] = true;
      std::fprintf(stderr, "fovlab: %s: %s, left out\n", log_paths[found.log].c_str(), found.reason.c_str());
    } else {
      mark_inconsistent(records[found.log].integrity, LogInconsistency{found.line, found.reason});
    }
  }
  // What only replay checked before: the header against its own config, the trials against the
  // schedule it makes (log_consistency.h); each distinct config read once.
  LoggedConfigs configs;
  for (size_t log_index = 0; log_index < log_paths.size(); ++log_index) {
    if (copy[log_index]) continue;
    current = log_paths[log_index];
    SessionRecord& record = records[log_index];
    if (record.integrity.status != LogStatus::broken)
      mark_inconsistent(record.integrity, check_log_against_header(record.header, record, current, configs));
    if (const auto fields = record.header.find("participant_fields");
        fields != record.header.end() && fields->is_object())
      for (const auto& [name, value] : fields->items()) field_names.insert(name);
  }
  std::ostringstream csv, steps;
  std::vector<std::string> header_row(std::begin(columns), std::end(columns));
  for (const std::string& name : field_names) header_row.push_back("field_" + name);
  header_row.insert(header_row.end(), std::begin(last_columns), std::end(last_columns));
  csv << csv_line(header_row);
  steps << csv_line(std::vector<std::string>(std::begin(step_columns), std::end(step_columns)));
  for (size_t log_index = 0; log_index < log_paths.size(); ++log_index) {
    if (copy[log_index]) continue;
    const std::string& path = log_paths[log_index];
    current = path;
    if (torn_bytes[log_index] > 0)
      std::fprintf(stderr, "fovlab: %s: the last line is cut off (%zu bytes); not exported\n", path.c_str(),
                   torn_bytes[log_index]);
    const SessionRecord& record = records[log_index];
    const LogIntegrity& integrity = record.integrity;
    std::vector<std::string> field_cells;
    for (const std::string& name : field_names) {
      const auto fields = record.header.find("participant_fields");
      const bool has =
          fields != record.header.end() && fields->is_object() && fields->contains(name) && (*fields)[name].is_string();
      field_cells.push_back(has ? (*fields)[name].get<std::string>() : "");
    }
    if (integrity.status == LogStatus::broken && !options.include_broken)
      throw InputError(path + ":" + std::to_string(integrity.line) + ": the log is broken (" + integrity.reason +
                       "); not exported (pass --include-broken to export it anyway, marked broken)");
    if (integrity.status != LogStatus::sealed || integrity.macs_not_checked())
      std::fprintf(stderr, "fovlab: %s: %s\n", path.c_str(), integrity.describe().c_str());
    const nlohmann::json& header = record.header;
    const std::string observer = observer_kind(header);  // "human" or "simulated"
    const std::string protocol = header.value("protocol", "");
    const std::string parameter = level_parameter(header, path, configs);
    nlohmann::json refresh_hz;
    if (const auto display = header.find("display"); display != header.end() && display->is_object()) {
      const auto measured = display->find("measured_refresh_hz");
      refresh_hz = measured != display->end() && measured->is_number() ? *measured
                                                                       : display->value("refresh_hz", nlohmann::json());
    }
    const std::vector<TrackNames> tracks = track_names(header, record, path, configs);
    const std::string gaze_source = gaze_kinds_text(session_gaze_kinds(header, record.resumes));
    std::map<int, std::pair<std::string, std::string>> blocks;  // index -> name, scene
    for (const BlockStartEvent& event : record.blocks) blocks[event.block] = {event.name, event.scene};
    // The repeat index: how many earlier trials of the log showed the same condition.
    std::map<std::tuple<int, std::string, std::string, bool>, int> repeats;
    for (const RecordedTrial& trial : record.trials) {
      const TrialStartEvent& start = trial.start;
      const int repeat = repeats[{start.block, start.condition, start.variant, start.attention_check}]++;
      std::string answers, answer, key;
      for (const ResponseEvent& response : trial.responses) {
        if (!answers.empty()) answers += ';';
        answers += response.answer;
        answer = response.answer;
        key = response.key;
      }
      nlohmann::json rt, saved_level, onset, dropped = 0, late;
      if (trial.responses.size() == 1) rt = optional_json(trial.responses.front().rt_s);
      for (const SliderSavedEvent& saved : trial.slider_saved) saved_level = optional_json(saved.level);
      if (!trial.stimuli.empty()) onset = trial.stimuli.front().onset_s;
      for (const StimulusEvent& shown : trial.stimuli) {
        dropped = dropped.get<int>() + shown.dropped_frames;
        if (shown.late_frames) late = late.is_null() ? *shown.late_frames : late.get<int>() + *shown.late_frames;
      }
      const int block = start.block;
      const auto block_info = blocks.count(block) ? blocks[block] : std::pair<std::string, std::string>();
      const std::string attention_correct =
          trial.attention_check ? number_cell(optional_json(trial.attention_check->correct)) : "";
      const bool named_track = start.track && *start.track >= 0 && static_cast<size_t>(*start.track) < tracks.size();
      const TrackNames track = named_track ? tracks[static_cast<size_t>(*start.track)] : TrackNames{};
      const std::vector<std::string> cells = {
          header.value("study", ""),
          header.value("participant", ""),
          observer,
          protocol,
          std::to_string(trial.index),
          std::to_string(block),
          block_info.first,
          block_info.second,
          start.condition,
          start.variant,
          number_cell(optional_json(start.level)),
          number_cell(start.attention_check),
          number_cell(optional_json(start.reference_first)),
          number_cell(optional_json(start.ramp_toward_reference)),
          answer,
          answers,
          number_cell(rt),
          number_cell(saved_level),
          attention_correct,
          number_cell(onset),
          number_cell(optional_json(trial.end.stamp.t)),
          number_cell(dropped),
          record.excluded ? "true" : "false",
          log_status_name(integrity.status),
          key,
          attention_correct,  // defined for attention checks; a ramp's steps have theirs in steps.csv
          std::to_string(repeat),
          parameter,
          header.value("started_utc", ""),
          header.value("fovlab_version", ""),
          header.value("config_hash", ""),
          number_cell(refresh_hz),
          number_cell(start.practice),
          start.track ? std::to_string(*start.track) : "",
          track.procedure,
          track.kind,
          gaze_source.empty() ? "not recorded" : gaze_source};
      std::vector<std::string> row = cells;
      row.insert(row.end(), field_cells.begin(), field_cells.end());
      row.push_back(number_cell(late));  // last_columns
      csv << csv_line(row);

      // Ramp steps and slider actions, one row an answer. A ramp's step s shows sequence[s] after
      // sequence[s - 1]; a slider's action is taken with the ladder at its current index (moved by
      // "up" and "down" from the trial's start).
      if (!start.ramp_toward_reference && !start.slider_start) continue;
      int ladder = start.slider_start.value_or(0);
      Trial ladder_trial;  // the session's own rule for moving along the ladder
      ladder_trial.sequence = start.sequence;
      for (const ResponseEvent& response : trial.responses) {
        nlohmann::json level, previous, correct;
        if (start.ramp_toward_reference) {
          const auto at = [&](int index) {
            return index >= 0 && size_t(index) < start.sequence.size()
                       ? stimulus_level(header, start.sequence[size_t(index)])
                       : nlohmann::json();
          };
          level = at(response.step);
          previous = at(response.step - 1);
          if (!response.answer.empty())
            correct = response.answer == answers::ramp_correct_answer(*start.ramp_toward_reference);
        } else {
          if (ladder >= 0 && size_t(ladder) < start.sequence.size())
            level = stimulus_level(header, start.sequence[size_t(ladder)]);
          ladder = next_ladder_index(ladder_trial, response.answer, ladder);
        }
        steps << csv_line(std::vector<std::string>{
            header.value("study", ""), header.value("participant", ""), observer, protocol, std::to_string(trial.index),
            std::to_string(response.step), number_cell(level), number_cell(previous), response.answer, response.key,
            number_cell(optional_json(response.rt_s)), number_cell(correct), log_status_name(integrity.status),
            number_cell(start.practice)});
      }
    }
  }
  return {csv.str(), steps.str()};
}

}  // namespace

ExportedCsv export_session_csvs(const std::vector<std::string>& log_paths, const ExportOptions& options) {
  std::string current;
  try {
    return export_checked(log_paths, options, current);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(current + ": an event has a field of the wrong type (" + error.what() + ")");
  }
}

std::string export_trials_csv(const std::vector<std::string>& log_paths, const ExportOptions& options) {
  return export_session_csvs(log_paths, options).trials;
}

}  // namespace fovlab
