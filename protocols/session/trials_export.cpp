#include "protocols/session/trials_export.h"

#include <cstdio>
#include <sstream>

#include "core/csv.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "study/log/session_record.h"

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

const char* const columns[] = {"study", "participant", "observer", "protocol", "trial", "block", "block_name", "scene",
                               "condition", "variant", "level", "attention_check", "reference_first",
                               "ramp_toward_reference", "answer", "answers", "rt_s", "saved_level",
                               "attention_correct", "onset_s", "end_s", "dropped_frames", "excluded", "log_status"};

}  // namespace


namespace {

// The export; `current` names the log being read, for the caller's message.
std::string export_checked(const std::vector<std::string>& log_paths, const ExportOptions& options, std::string& current) {
  std::ostringstream csv;
  csv << csv_line(std::vector<std::string>(std::begin(columns), std::end(columns)));
  for (const std::string& path : log_paths) {
    current = path;
    const EventLogFile log = read_event_log(path);
    if (log.torn_tail)
      std::fprintf(stderr, "fovlab: %s: the last line is cut off (%zu bytes); not exported\n", path.c_str(),
                   log.torn_tail->size());
    const SessionRecord record = read_session_record(log, options.lab_key);
    const LogIntegrity& integrity = record.integrity;
    if (integrity.status == LogStatus::broken && !options.include_broken)
      throw InputError(path + ":" + std::to_string(integrity.line) + ": the log is broken (" + integrity.reason +
                       "); not exported (pass --include-broken to export it anyway, marked broken)");
    if (integrity.status != LogStatus::sealed)
      std::fprintf(stderr, "fovlab: %s: %s\n", path.c_str(), integrity.describe().c_str());
    const nlohmann::json& header = record.header;
    const std::string observer = observer_kind(header);  // "human" or "simulated"
    std::map<int, std::pair<std::string, std::string>> blocks;  // index -> name, scene
    for (const BlockStartEvent& event : record.blocks) blocks[event.block] = {event.name, event.scene};
    for (const RecordedTrial& trial : record.trials) {
      const TrialStartEvent& start = trial.start;
      std::string answers, answer;
      for (const ResponseEvent& response : trial.responses) {
        if (!answers.empty()) answers += ';';
        answers += response.answer;
        answer = response.answer;
      }
      nlohmann::json rt, saved_level, onset, dropped = 0;
      if (trial.responses.size() == 1) rt = optional_json(trial.responses.front().rt_s);
      for (const SliderSavedEvent& saved : trial.slider_saved) saved_level = optional_json(saved.level);
      if (!trial.stimuli.empty()) onset = trial.stimuli.front().onset_s;
      for (const StimulusEvent& shown : trial.stimuli) dropped = dropped.get<int>() + shown.dropped_frames;
      const int block = start.block;
      const auto block_info = blocks.count(block) ? blocks[block] : std::pair<std::string, std::string>();
      const std::vector<std::string> cells = {
          header.value("study", ""),
          header.value("participant", ""),
          observer,
          header.value("protocol", ""),
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
          trial.attention_check ? number_cell(optional_json(trial.attention_check->correct)) : "",
          number_cell(onset),
          number_cell(optional_json(trial.end.stamp.t)),
          number_cell(dropped),
          record.excluded ? "true" : "false",
          log_status_name(integrity.status)};
      csv << csv_line(cells);
    }
  }
  return csv.str();
}

}  // namespace

std::string export_trials_csv(const std::vector<std::string>& log_paths, const ExportOptions& options) {
  std::string current;
  try {
    return export_checked(log_paths, options, current);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(current + ": an event has a field of the wrong type (" + error.what() + ")");
  }
}

}  // namespace fovlab
