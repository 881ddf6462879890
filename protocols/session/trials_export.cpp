#include "protocols/session/trials_export.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/input_error.h"
#include "core/number_text.h"
#include "protocols/log/session_record.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string number_cell(const nlohmann::json& value) {
  if (value.is_null()) return "";
  if (value.is_number_integer()) return std::to_string(value.get<int64_t>());
  if (value.is_number()) return format_number(value.get<double>(), 10);
  if (value.is_boolean()) return value.get<bool>() ? "true" : "false";
  return csv_cell(value.is_string() ? value.get<std::string>() : value.dump());
}

const char* const columns[] = {"study", "participant", "protocol", "trial", "block", "block_name", "scene",
                               "condition", "variant", "level", "attention_check", "reference_first",
                               "ramp_toward_reference", "answer", "answers", "rt_s", "saved_level",
                               "attention_correct", "onset_s", "end_s", "dropped_frames", "excluded"};

}  // namespace

std::vector<std::string> find_session_logs(const std::string& path) {
  std::vector<std::string> logs;
  if (fs::is_regular_file(path)) return {path};
  if (!fs::is_directory(path)) throw InputError(path + ": no such log file or results folder");
  for (const auto& entry : fs::recursive_directory_iterator(path))
    if (entry.is_regular_file() && entry.path().filename() == "events.jsonl") logs.push_back(entry.path().string());
  std::sort(logs.begin(), logs.end());
  if (logs.empty()) throw InputError(path + ": no events.jsonl under this folder");
  return logs;
}

namespace {

// The export; `current` names the log being read, for the caller's message.
std::string export_checked(const std::vector<std::string>& log_paths, std::string& current) {
  std::ostringstream csv;
  for (size_t i = 0; i < std::size(columns); ++i) csv << (i ? "," : "") << columns[i];
  csv << "\n";
  for (const std::string& path : log_paths) {
    current = path;
    const EventLogFile log = read_event_log(path);
    if (log.torn_tail)
      std::fprintf(stderr, "fovlab: %s: the last line is cut off (%zu bytes); not exported\n", path.c_str(),
                   log.torn_tail->size());
    const SessionRecord record = read_session_record(log);
    const nlohmann::json& header = record.header;
    std::map<int, std::pair<std::string, std::string>> blocks;  // index -> name, scene
    for (const nlohmann::json& event : log.events)
      if (event.value("event", "") == "block_start")
        blocks[event.value("block", 0)] = {event.value("name", ""), event.value("scene", "")};
    for (const RecordedTrial& trial : record.trials) {
      const nlohmann::json& start = trial.start;
      std::string answers, answer;
      for (const nlohmann::json& response : trial.responses) {
        if (!answers.empty()) answers += ';';
        answers += response.value("answer", std::string());
        answer = response.value("answer", std::string());
      }
      nlohmann::json rt, saved_level, onset, dropped = 0;
      if (trial.responses.size() == 1) rt = trial.responses.front().value("rt_s", nlohmann::json());
      for (const nlohmann::json& other : trial.other)
        if (other.value("event", "") == "slider_saved") saved_level = other.value("level", nlohmann::json());
      if (!trial.stimuli.empty()) onset = trial.stimuli.front().value("onset_s", nlohmann::json());
      for (const nlohmann::json& shown : trial.stimuli) dropped = dropped.get<int>() + shown.value("dropped_frames", 0);
      const int block = start.value("block", 0);
      const auto block_info = blocks.count(block) ? blocks[block] : std::pair<std::string, std::string>();
      const std::vector<std::string> cells = {
          csv_cell(header.value("study", "")),
          csv_cell(header.value("participant", "")),
          csv_cell(header.value("protocol", "")),
          std::to_string(trial.index),
          std::to_string(block),
          csv_cell(block_info.first),
          csv_cell(block_info.second),
          csv_cell(start.value("condition", "")),
          csv_cell(start.value("variant", "")),
          number_cell(start.value("level", nlohmann::json())),
          number_cell(start.value("attention_check", false)),
          number_cell(start.value("reference_first", nlohmann::json())),
          number_cell(start.value("ramp_toward_reference", nlohmann::json())),
          csv_cell(answer),
          csv_cell(answers),
          number_cell(rt),
          number_cell(saved_level),
          trial.attention_check ? number_cell(trial.attention_check->value("correct", nlohmann::json())) : "",
          number_cell(onset),
          number_cell(trial.end.value("t", nlohmann::json())),
          number_cell(dropped),
          record.excluded ? "true" : "false"};
      for (size_t i = 0; i < cells.size(); ++i) csv << (i ? "," : "") << cells[i];
      csv << "\n";
    }
  }
  return csv.str();
}

}  // namespace

std::string export_trials_csv(const std::vector<std::string>& log_paths) {
  std::string current;
  try {
    return export_checked(log_paths, current);
  } catch (const nlohmann::json::exception& error) {
    throw InputError(current + ": an event has a field of the wrong type (" + error.what() + ")");
  }
}

}  // namespace fovlab
