#include "analysis/study/study_data.h"

#include <algorithm>
#include <filesystem>
#include <iterator>
#include <atomic>
#include <thread>
#include <cctype>
#include <map>
#include <numbers>
#include <set>

#include "core/input_error.h"
#include "study/config/study_config.h"
#include "study/log/event_log.h"
#include "study/log/log_consistency.h"
#include "study/log/log_events.h"
#include "study/log/session_copies.h"
#include "study/log/session_scan.h"

namespace fovlab::analysis {
namespace {

std::optional<double> optional_number(const nlohmann::json& object, const char* key) {
  const auto found = object.find(key);
  if (found == object.end() || !found->is_number()) return std::nullopt;
  return found->get<double>();
}

// Which study (and config version) a log belongs to, from its header; the config text it carries
// is parsed once, for the study chosen (every log of it carries the same text: config_hash).
// What tells config versions apart: the content hash, or, for a config that cannot be read, its
// bytes' hash.
std::string version_key(const std::string& content_hash, const std::string& config_hash) {
  return content_hash.empty() ? "config_hash " + config_hash : content_hash;
}

struct LogStudy {
  std::string study, config_hash, config_toml, conditions_csv;
  std::string content_hash;  // the config's version, comments and formatting aside ("" when unreadable)
  int log_schema_version = 0;
  std::string version() const { return version_key(content_hash, config_hash); }
};

void describe_study(const LogStudy& study, const std::string& path, StudyData& data) {
  describe_study_config(parse_logged_study_config(study.config_toml, path + " (config_toml)", study.log_schema_version,
                                                  nullptr, study.conditions_csv),
                        data);
  data.study = study.study;
  data.config_hash = study.config_hash;
}

// The refresh rate a session's frames were presented at: the header's display.measured_refresh_hz
// (what the presenter measured), else the config's display.refresh_hz; none when neither is a
// positive number.
std::optional<double> header_refresh_hz(const nlohmann::json& header) {
  const auto display = header.find("display");
  if (display == header.end() || !display->is_object()) return std::nullopt;
  for (const char* key : {"measured_refresh_hz", "refresh_hz"})
    if (const std::optional<double> hz = optional_number(*display, key); hz && *hz > 0.0) return hz;
  return std::nullopt;
}

// The header's `headset`, read leniently (a field of another type is left out): the analysis
// reports it, and replay, not analyze, is where a header is checked whole.
std::optional<HeadsetSummary> header_headset(const nlohmann::json& header) {
  const auto found = header.find("headset");
  if (found == header.end() || !found->is_object()) return std::nullopt;
  const nlohmann::json& headset = *found;
  HeadsetSummary summary;
  const auto text = [](const nlohmann::json& object, const char* key) {
    const auto value = object.find(key);
    return value != object.end() && value->is_string() ? value->get<std::string>() : std::string();
  };
  const auto whole = [&](const char* key) {
    const std::optional<double> value = optional_number(headset, key);
    return value ? static_cast<int>(*value) : 0;
  };
  summary.runtime = text(headset, "runtime");
  summary.eye_width_px = whole("eye_width_px");
  summary.eye_height_px = whole("eye_height_px");
  summary.view_model = text(headset, "view_model");
  if (const auto fixation = headset.find("gaze_fixation"); fixation != headset.end() && fixation->is_object()) {
    summary.gaze_fixation = text(*fixation, "kind");
    summary.fixation_distance_mm = optional_number(*fixation, "distance_mm");
  }
  if (const auto eyes = headset.find("eyes"); eyes != headset.end() && eyes->is_array()) {
    for (size_t eye = 0; eye < 2 && eye < eyes->size(); ++eye) {
      const auto fov = (*eyes)[eye].is_object() ? (*eyes)[eye].find("fov_rad") : (*eyes)[eye].end();
      if (fov == (*eyes)[eye].end() || !fov->is_array() || fov->size() != 4) continue;
      std::array<double, 4> degrees{};
      bool numbers = true;
      for (size_t side = 0; side < 4; ++side) {
        numbers = numbers && (*fov)[side].is_number();
        if (numbers) degrees[side] = (*fov)[side].get<double>() * 180.0 / std::numbers::pi;
      }
      if (numbers) summary.fov_deg[eye] = degrees;
    }
  }
  return summary;
}

ParticipantData participant_of(ScannedSession& session) {
  // The level and method of every stimulus id (level none: a reference), from the header once.
  std::vector<std::optional<double>> level_of_stimulus;
  std::vector<std::string> method_of_stimulus;
  for (const nlohmann::json& stimulus : session.header.at("stimuli")) {
    const bool reference = stimulus.value("is_reference", false);
    level_of_stimulus.push_back(reference ? std::nullopt : optional_number(stimulus, "level"));
    method_of_stimulus.push_back(reference ? std::string() : stimulus.value("method", ""));
  }
  const auto stimulus_level = [&](int id) -> std::optional<double> {
    if (id < 0 || static_cast<size_t>(id) >= level_of_stimulus.size())
      throw InputError(session.path + ": stimulus " + std::to_string(id) + " is not in the header's stimuli");
    return level_of_stimulus[static_cast<size_t>(id)];
  };
  ParticipantData participant;
  participant.participant = session.header.value("participant", "");
  participant.log_path = session.path;
  participant.observer = observer_kind(session.header);
  participant.excluded = session.excluded;
  participant.session_ended = session.ended;
  participant.attention_errors = session.attention_errors;
  // Latency: every age of the complete trials, summarised here so the ages are not kept.
  // Frame intervals likewise, against the refresh rate the presenter measured (the header's display).
  std::vector<double> gaze_age_s, frame_interval_s;
  std::optional<int64_t> late_frames;  // a headset's, where its log measured them
  int64_t gaze_refreshes = 0;
  std::array<int64_t, 2> gaze_off_image = {0, 0}, gaze_invalid_other = {0, 0};  // left, right
  for (ScannedTrial& scanned : session.trials) {
    if (scanned.practice) continue;  // practice trials are in no figure
    participant.dropped_frames += scanned.dropped_frames;
    if (scanned.late_frames) late_frames = late_frames.value_or(0) + *scanned.late_frames;
    gaze_refreshes += scanned.gaze_refreshes;
    gaze_off_image[0] += scanned.gaze_off_image;
    gaze_invalid_other[0] += scanned.gaze_invalid_other;
    gaze_off_image[1] += scanned.right_gaze_off_image;
    gaze_invalid_other[1] += scanned.right_gaze_invalid_other;
    if (scanned.stimuli_with_latency > 0) participant.latency_recorded = true;
    gaze_age_s.insert(gaze_age_s.end(), scanned.gaze_age_s.begin(), scanned.gaze_age_s.end());
    scanned.gaze_age_s = {};
    frame_interval_s.insert(frame_interval_s.end(), scanned.frame_interval_s.begin(), scanned.frame_interval_s.end());
    scanned.frame_interval_s = {};
  }
  participant.latency = summarise_latency(gaze_age_s);
  participant.gaze_kinds = session_gaze_kinds(session.header, session.resumes);
  participant.gaze_source = gaze_kinds_text(participant.gaze_kinds);
  participant.frame_intervals = summarise_frame_intervals(frame_interval_s, header_refresh_hz(session.header));
  for (const std::string& clock : session.present_clocks)
    participant.present_clock += (participant.present_clock.empty() ? "" : "+") + clock;
  participant.headset = header_headset(session.header);
  if (participant.headset) {
    participant.headset->late_frames = late_frames;
    participant.headset->gaze_refreshes = gaze_refreshes;
    participant.headset->gaze_off_image = gaze_off_image;
    participant.headset->gaze_invalid_other = gaze_invalid_other;
    participant.headset->right_eye_marked = header_schema_version(session.header) >= 13;
  }
  for (const TrackerValidationEvent& attempt : session.validations) {
    ValidationSummary& validation = participant.validation;
    ++validation.attempts;
    if (!attempt.passed || !attempt.accuracy_deg || !attempt.precision_deg) continue;
    const double count = ++validation.passed;
    validation.mean_accuracy_deg = validation.mean_accuracy_deg.value_or(0.0) +
                                   (*attempt.accuracy_deg - validation.mean_accuracy_deg.value_or(0.0)) / count;
    validation.mean_precision_deg = validation.mean_precision_deg.value_or(0.0) +
                                    (*attempt.precision_deg - validation.mean_precision_deg.value_or(0.0)) / count;
    validation.worst_accuracy_deg = std::max(validation.worst_accuracy_deg.value_or(0.0), *attempt.accuracy_deg);
  }
  for (ScannedTrial& scanned : session.trials) {
    // Practice trials teach the task; no analysis counts them.
    if (scanned.practice) {
      ++participant.practice_trials;
      continue;
    }
    StudyTrial trial;
    trial.index = scanned.index;
    trial.scene = session.block_names[scanned.block];
    trial.condition = std::move(scanned.condition);
    trial.variant = std::move(scanned.variant);
    trial.level = scanned.level;
    trial.attention_check = scanned.attention_check;
    trial.reference_first = scanned.reference_first.value_or(true);
    trial.ramp_toward_reference = scanned.ramp_toward_reference;
    if (!trial.attention_check)
      for (int id : scanned.sequence) {
        trial.sequence_levels.push_back(stimulus_level(id));
        if (trial.method.empty()) trial.method = method_of_stimulus[static_cast<size_t>(id)];
      }
    trial.answers = std::move(scanned.answers);
    trial.answer_steps = std::move(scanned.answer_steps);
    trial.saved_level = scanned.saved_level;
    trial.track = scanned.track;
    if (trial.attention_check) ++participant.attention_checks;
    participant.trials.push_back(std::move(trial));
  }
  return participant;
}

// One log, read: its study, its participant, and notes on what of it was not read.
struct ReadLog {
  std::optional<LogStudy> study;  // none: the log could not be read (reason in notes)
  ParticipantData participant;
  LogIntegrity integrity;       // with the checks against its own header (log_consistency.h)
  SessionLogIdentity identity;  // which session it is a log of (session_copies.h)
  std::vector<LeftOut> notes;
};

LeftOut left_out(const std::string& path, std::string reason) {
  if (reason.rfind(path + ":", 0) == 0) reason = reason.substr(path.size() + 1);  // the path is named once
  while (!reason.empty() && reason.front() == ' ') reason.erase(reason.begin());
  if (!reason.empty() && std::isdigit(static_cast<unsigned char>(reason.front()))) reason = "line " + reason;
  return {path, reason};
}

ReadLog read_log(const std::string& path, const LoadOptions& options, LoggedConfigs& configs) {
  ReadLog read;
  try {
    ScannedSession session = scan_session_log(path, options.lab_key);
    LogIntegrity& integrity = session.integrity;
    // What only replay checked before: the header against its own config, the trials against the
    // schedule it makes (each distinct config read once, for every thread).
    if (integrity.status != LogStatus::broken)
      mark_inconsistent(integrity, check_log_against_header(session.header, session, path, configs));
    read.integrity = integrity;
    read.identity = {path, session.header_chain, session.header.value("participant", ""), session.line_count,
                     session.first_chain_error_line};
    read.study = LogStudy{session.header.value("study", ""),
                          session.header.value("config_hash", ""),
                          session.header.value("config_toml", ""),
                          session.header.value("conditions_csv", ""),
                          std::string(),
                          integrity.schema_version};
    std::string config_error;
    if (const std::shared_ptr<const StudyConfig> config = configs.config_of(session.header, path, config_error))
      read.study->content_hash = config->content_hash;
    // The study names the default output folder (results/<study>/analysis): the scan refused a
    // header whose study is not one folder name ("../../x", "/tmp/x"; check_session_header).
    read.participant = participant_of(session);
    if (session.torn_tail_bytes)
      read.notes.push_back({path, "the last line is cut off (" + std::to_string(session.torn_tail_bytes) +
                                      " bytes, a write a crash interrupted): not read"});
    if (session.incomplete_trial >= 0)
      read.notes.push_back(
          {path, "trial " + std::to_string(session.incomplete_trial) + " was started but not finished: not counted"});
  } catch (const InputError& error) {
    read.study.reset();
    read.notes = {left_out(path, error.what())};
  } catch (const nlohmann::json::exception& error) {
    read.study.reset();
    read.notes = {left_out(path, std::string("an event has a field of the wrong type (") + error.what() + ")")};
  } catch (const std::exception& error) {  // e.g. out of memory for a huge file: this log only
    read.study.reset();
    read.notes = {left_out(path, std::string("cannot be read (") + error.what() + ")")};
  }
  return read;
}

// Every log, read by as many threads as the machine has cores (each log by one thread).
std::vector<ReadLog> read_logs(const std::vector<std::string>& paths, const LoadOptions& options) {
  std::vector<ReadLog> logs(paths.size());
  LoggedConfigs configs;
  std::atomic<size_t> next{0};
  const auto work = [&] {
    for (size_t i = next++; i < paths.size(); i = next++) logs[i] = read_log(paths[i], options, configs);
  };
  const size_t thread_count = std::min<size_t>(paths.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (size_t i = 1; i < thread_count; ++i) threads.emplace_back(work);
  work();
  for (std::thread& thread : threads) thread.join();
  return logs;
}

// One session counted once: a copy of another log of its session is left out, two logs of one
// session that part are broken (session_copies.h); then broken logs are left out unless asked for.
// What is kept carries its verdict in words.
void take_sessions_once(std::vector<ReadLog>& logs, const LoadOptions& options) {
  std::vector<SessionLogIdentity> identities;
  std::vector<size_t> read_index;
  for (size_t i = 0; i < logs.size(); ++i)
    if (logs[i].study) {
      identities.push_back(logs[i].identity);
      read_index.push_back(i);
    }
  for (const SessionCopy& found : find_session_copies(identities)) {
    ReadLog& read = logs[read_index[found.log]];
    if (found.kind == SessionCopy::Kind::diverged) {
      mark_inconsistent(read.integrity, LogInconsistency{found.line, found.reason});
      continue;
    }
    read.notes = {{read.identity.path, found.reason}};
    read.study.reset();
  }
  for (ReadLog& read : logs) {
    if (!read.study) continue;
    const LogIntegrity& integrity = read.integrity;
    if (integrity.status == LogStatus::broken && !options.include_broken) {
      read.notes = {{read.identity.path, "line " + std::to_string(integrity.line) + ": the log is broken (" +
                                             integrity.reason + "); left out (--include-broken analyses it anyway)"}};
      read.study.reset();
      continue;
    }
    read.participant.log_status = integrity.status;
    if (integrity.status != LogStatus::sealed || integrity.macs_not_checked())
      read.participant.log_note = integrity.describe();
  }
}

// Refuses logs of several studies, naming each with its count of logs (most first) and the folder
// of the first log of the one with most.
void require_one_study(const std::vector<ReadLog>& logs) {
  std::map<std::string, int> logs_per_study;
  std::map<std::string, std::string> first_log;
  for (const ReadLog& read : logs) {
    if (!read.study) continue;
    ++logs_per_study[read.study->study];
    first_log.emplace(read.study->study, read.participant.log_path);
  }
  if (logs_per_study.size() < 2) return;
  std::vector<std::pair<int, std::string>> counts;
  for (const auto& [study, count] : logs_per_study) counts.emplace_back(-count, study);
  std::sort(counts.begin(), counts.end());
  std::string studies;
  for (const auto& [count, study] : counts)
    studies += (studies.empty() ? "" : ", ") + study + " " + std::to_string(-count);
  // results/<study>/<participant>/events.jsonl: the study's folder is two up.
  const std::filesystem::path folder =
      std::filesystem::path(first_log[counts.front().second]).parent_path().parent_path();
  throw InputError("session logs of " + std::to_string(counts.size()) + " studies (" + studies +
                   " logs): analyse one study at a time, e.g. " + folder.string());
}

// Keeps the readable logs answered by the observers asked for, the others left out (before the
// config version and duplicate IDs are looked at, so neither is decided by a session not analysed);
// by default a mix of human and simulated sessions is refused. Returns who answered those kept.
std::string take_observers(std::vector<ReadLog>& logs, ObserverFilter filter, std::vector<LeftOut>& left_out) {
  int human = 0, simulated = 0;
  std::string study;
  for (const ReadLog& read : logs) {
    if (!read.study) continue;
    ++(read.participant.observer == "human" ? human : simulated);
    study = read.study->study;
  }
  if (filter == ObserverFilter::all)
    return human && simulated ? "human and simulated" : simulated ? "simulated" : "human";
  if (filter == ObserverFilter::unmixed) {
    if (human && simulated)
      throw InputError("study " + study + ": " + std::to_string(human) + " human and " + std::to_string(simulated) +
                       " simulated session(s): analyse real participants with --observers human, the simulated "
                       "ones with --observers simulated, or pool them knowingly with --observers all");
    return simulated ? "simulated" : "human";
  }
  const std::string kept = filter == ObserverFilter::human ? "human" : "simulated";
  if ((filter == ObserverFilter::human ? human : simulated) == 0)
    throw InputError("study " + study + ": no session answered by a " + kept + " observer (--observers " + kept + ")");
  for (ReadLog& read : logs) {
    if (!read.study || read.participant.observer == kept) continue;
    left_out.push_back({read.participant.log_path,
                        "answered by a " + read.participant.observer + " observer (--observers " + kept + ")"});
    read.study.reset();
    read.notes.clear();
  }
  return kept;
}

std::string kinds_text(const std::vector<GazeSourceKind>& kinds, const char* separator) {
  std::string text;
  for (GazeSourceKind kind : kinds) text += (text.empty() ? "" : separator) + std::string(gaze_source_kind_name(kind));
  return text;
}

bool uses(const ParticipantData& participant, GazeSourceKind kind) {
  return std::find(participant.gaze_kinds.begin(), participant.gaze_kinds.end(), kind) != participant.gaze_kinds.end();
}

// Keeps the sessions of the gaze sources asked for (after the config version and duplicate IDs were
// decided), the others left out and named. By default only a gaze-contingent study is looked at:
// its mouse sessions (rehearsals) are left out when other sessions had gaze from elsewhere.
void take_gaze_sources(StudyData& data, const GazeSourceFilter& filter) {
  const bool contingent = is_gaze_contingent(data.config);
  std::vector<ParticipantData> kept;
  const auto gaze_of = [](const ParticipantData& participant) {
    return participant.gaze_kinds.empty() ? std::string("a source not recorded")
                                          : "the " + kinds_text(participant.gaze_kinds, " and the ");
  };
  if (!filter.kinds.empty()) {
    const std::string asked = kinds_text(filter.kinds, ",");
    for (ParticipantData& participant : data.participants) {
      const bool taken =
          !participant.gaze_kinds.empty() &&
          std::all_of(participant.gaze_kinds.begin(), participant.gaze_kinds.end(), [&](GazeSourceKind kind) {
            return std::find(filter.kinds.begin(), filter.kinds.end(), kind) != filter.kinds.end();
          });
      if (taken) kept.push_back(std::move(participant));
      else
        data.left_out.push_back(
            {participant.log_path, "gaze from " + gaze_of(participant) + " (--gaze-sources " + asked + ")"});
    }
    if (kept.empty())
      throw InputError("study " + data.study +
                       ": no session with gaze from a source of the kinds asked for (--gaze-sources " + asked + ")");
    data.participants = std::move(kept);
    if (contingent && std::all_of(data.participants.begin(), data.participants.end(),
                                  [](const ParticipantData& p) { return uses(p, GazeSourceKind::mouse); }))
      data.gaze_note = "mouse gaze: rehearsals";
    return;
  }
  if (!contingent) return;
  const auto mouse = std::count_if(data.participants.begin(), data.participants.end(),
                                   [](const ParticipantData& p) { return uses(p, GazeSourceKind::mouse); });
  const auto others = static_cast<std::ptrdiff_t>(data.participants.size()) - mouse;
  if (mouse == 0) return;
  if (filter.all) {
    data.gaze_note =
        others > 0 ? "mouse gaze pooled with the other sources by --gaze-sources all" : "mouse gaze: rehearsals";
    return;
  }
  if (others == 0) {
    data.gaze_note = "mouse gaze: rehearsals";
    return;
  }
  for (ParticipantData& participant : data.participants) {
    if (!uses(participant, GazeSourceKind::mouse)) {
      kept.push_back(std::move(participant));
      continue;
    }
    data.left_out.push_back(
        {participant.log_path, "gaze from " + gaze_of(participant) +
                                   " (a rehearsal of a gaze-contingent study), kept apart from the " +
                                   std::to_string(others) +
                                   " session(s) with gaze from another source; --gaze-sources all "
                                   "pools them, --gaze-sources mouse analyses them alone"});
  }
  data.participants = std::move(kept);
}

}  // namespace

GazeSourceFilter parse_gaze_source_filter(const std::string& text) {
  GazeSourceFilter filter;
  if (text == "all") {
    filter.all = true;
    return filter;
  }
  size_t begin = 0;
  while (true) {
    const size_t comma = text.find(',', begin);
    const std::string name = text.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
    const std::optional<GazeSourceKind> kind = parse_gaze_source_kind(name);
    if (!kind || std::find(filter.kinds.begin(), filter.kinds.end(), *kind) != filter.kinds.end())
      throw InputError(
          "--gaze-sources: expected all, or gaze source kinds (tracker, trace, synthetic, mouse) separated by "
          "commas, each once, got \"" +
          text + "\"");
    filter.kinds.push_back(*kind);
    if (comma == std::string::npos) break;
    begin = comma + 1;
  }
  return filter;
}

std::optional<ObserverFilter> parse_observer_filter(const std::string& text) {
  if (text == "human") return ObserverFilter::human;
  if (text == "simulated") return ObserverFilter::simulated;
  if (text == "all") return ObserverFilter::all;
  return std::nullopt;
}

const std::vector<double>& StudyData::levels_of(const std::string& variant) const {
  const auto found =
      std::find_if(variants.begin(), variants.end(), [&](const VariantConfig& v) { return v.name == variant; });
  return found != variants.end() && !found->levels.empty() ? found->levels : levels;
}

StudyData load_study(const std::vector<std::string>& paths, const LoadOptions& options) {
  std::set<std::string> unique_logs;
  for (const std::string& path : paths)
    for (const std::string& log : find_session_logs(path)) unique_logs.insert(log);
  StudyData data;
  data.inputs.assign(unique_logs.begin(), unique_logs.end());
  std::vector<ReadLog> logs = read_logs(data.inputs, options);
  take_sessions_once(logs, options);
  require_one_study(logs);
  data.observers = take_observers(logs, options.observers, data.left_out);

  // The study (and config) most readable logs belong to is analysed; ties: the one whose first log
  // comes first in path order.
  std::map<std::pair<std::string, std::string>, int> logs_per_study;
  for (const ReadLog& read : logs)
    if (read.study) ++logs_per_study[{read.study->study, read.study->version()}];
  const LogStudy* study = nullptr;
  std::string study_path;  // the study's first log, named if its config cannot be read
  for (const ReadLog& read : logs) {
    if (read.study && (!study || logs_per_study[{read.study->study, read.study->version()}] >
                                     logs_per_study[{study->study, study->version()}])) {
      study = &*read.study;
      study_path = read.participant.log_path;
    }
  }
  if (!study) {
    const LeftOut& first = logs.empty() ? LeftOut{"", "no session log to analyse"} : logs.front().notes.front();
    throw InputError(first.what.empty() ? first.reason : first.what + ": " + first.reason);
  }

  // Every version, the analysed one first, then by sessions (ties: the first log's path order).
  for (const ReadLog& read : logs) {
    if (!read.study) continue;
    const std::string version = read.study->version();
    auto found = std::find_if(
        data.config_versions.begin(), data.config_versions.end(),
        [&](const ConfigVersion& known) { return version_key(known.content_hash, known.config_hash) == version; });
    if (found == data.config_versions.end()) {
      data.config_versions.push_back(
          {read.study->content_hash, read.study->config_hash, 0, {}, version == study->version()});
      found = std::prev(data.config_versions.end());
    }
    ++found->sessions;
    // results/<folder>/<participant>/events.jsonl: the study's folder is two up.
    const std::string folder =
        std::filesystem::path(read.participant.log_path).parent_path().parent_path().lexically_normal().string();
    if (std::find(found->folders.begin(), found->folders.end(), folder) == found->folders.end())
      found->folders.push_back(folder);
  }
  std::stable_sort(data.config_versions.begin(), data.config_versions.end(),
                   [](const ConfigVersion& a, const ConfigVersion& b) {
                     return a.analysed != b.analysed ? a.analysed : a.sessions > b.sessions;
                   });

  std::map<std::string, std::string> log_of_participant;
  for (ReadLog& read : logs) {
    const std::string& path = read.participant.log_path;
    if (!read.study) {
      data.left_out.insert(data.left_out.end(), read.notes.begin(), read.notes.end());
      continue;
    }
    if (read.study->version() != study->version()) continue;  // counted in config_versions
    const auto [previous, inserted] = log_of_participant.emplace(read.participant.participant, path);
    if (!inserted) {
      data.left_out.push_back({path, "participant " + read.participant.participant + " is also in " + previous->second +
                                         " (duplicate participant ID; the first log is used)"});
      continue;
    }
    data.left_out.insert(data.left_out.end(), read.notes.begin(), read.notes.end());
    data.participants.push_back(std::move(read.participant));
  }
  describe_study(*study, study_path, data);
  take_gaze_sources(data, options.gaze_sources);
  return data;
}

void describe_study_config(const StudyConfig& config, StudyData& data) {
  data.study = config.name;
  data.config_hash = config.hash;
  data.protocol = config.protocol.kind;
  data.question = config.protocol.two_afc_question;
  data.level_parameter = config.levels.parameter;
  data.levels = config.levels.values;
  data.higher_is_better = config.levels.higher_is_better;
  data.reference_method = config.stimulus.reference.method;
  data.test_method = config.stimulus.test.method;
  data.variants = config.stimulus.variants;
  data.config = config;
}

}  // namespace fovlab::analysis
