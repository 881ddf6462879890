#include "protocols/session/session.h"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <optional>

#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/output_guard.h"
#include "core/session_files.h"
#include "core/test_pause.h"
#include "protocols/gaze/gaze_source.h"
#include "protocols/gaze/gaze_spec.h"
#include "protocols/gaze/mouse_gaze_source.h"
#include "protocols/gaze/openxr_gaze_source.h"
#include "study/log/event_log.h"
#include "study/log/log_events.h"
#include "study/log/log_integrity.h"
#include "study/log/participant_lock.h"
#include "study/log/session_record.h"
#include "study/log/schedule_check.h"
#include "study/log/study_versions.h"
#include "display/headless_presenter.h"
#include "display/openxr/openxr_eye_view.h"
#include "display/openxr/openxr_presenter.h"
#include "display/text_screen.h"
#include "display/window_presenter.h"
#include "study/log/log_estimate.h"
#include "study/schedule/study_plan.h"
#include "protocols/session/head_tracking.h"
#include "protocols/session/headset_views.h"
#include "protocols/session/response_source.h"
#include "protocols/session/session_header.h"
#include "protocols/session/session_run.h"
#include "protocols/stimuli/plan_renderable.h"
#include "protocols/stimuli/image_sequence.h"
#include "protocols/stimuli/stimulus_library.h"
#include "protocols/stimuli/stimulus_renderer.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "renderer/vk/context.h"

namespace fovlab {
namespace {

namespace fs = std::filesystem;

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  return text;
}

// Moves an unterminated last line aside (events.jsonl.torn-N, fsync'd) and cuts it off the log. The
// caller holds the participant's lock. A failure (a full disk) leaves neither an empty or partial
// torn-N file nor a changed log.
std::string set_torn_tail_aside(const EventLogFile& log) {
  std::string aside;
  for (int n = 1;; ++n) {
    aside = set_aside_path(log.path, SetAside::torn, n).string();
    if (!fs::exists(fs::symlink_status(aside))) break;
  }
  {
    const int fd = ::open(aside.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) throw FileError(aside, "creating the file for the cut-off last line", errno);
    const std::string& tail = *log.torn_tail;
    const bool written = ::write(fd, tail.data(), tail.size()) == static_cast<ssize_t>(tail.size());
    const int reason = written ? 0 : (errno ? errno : ENOSPC);
    const bool synced = written && ::fsync(fd) == 0;
    const int sync_reason = errno;
    ::close(fd);
    if (!synced) {
      ::unlink(aside.c_str());
      throw FileError(aside, "writing the cut-off last line aside", written ? sync_reason : reason);
    }
  }
  fsync_directory(fs::path(aside).parent_path());
  const int fd = ::open(log.path.c_str(), O_WRONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0 || ::ftruncate(fd, static_cast<off_t>(log.intact_bytes)) != 0 || ::fsync(fd) != 0) {
    const int reason = errno;
    if (fd >= 0) ::close(fd);
    throw FileError(log.path, "cutting off the torn last line", reason);
  }
  ::close(fd);
  return aside;
}

// A resumed log must be one this plan made: every complete trial within the plan and as the plan
// (with its adaptive tracks' answers so far) presents it, none missing (a forged log cannot make a
// session "131 of 89 trials complete"). Returns the tracks' progress to continue from.
ScheduleCheck check_trials_against_plan(const SessionRecord& record, const StudyPlan& plan,
                                        const std::string& log_path) {
  ScheduleCheck check = check_log_against_schedule(record, plan);
  if (!check.differences.empty())
    throw InputError(log_path + ": " + check.differences.front() +
                     "; the log was not written by this config; not resuming");
  return check;
}

// A session that found its log replaced under it copied its events to events.jsonl.recovered-N
// (study/log/event_log.h): that copy becomes the log again, and whatever another program left at
// the log's name is kept beside it as events.jsonl.replaced-N. The caller holds the lock.
void restore_recovered_log(const std::string& log_path) {
  const fs::path log(log_path);
  const std::string prefix = set_aside_name_prefix(log, SetAside::recovered);
  std::vector<fs::path> copies;
  for (const fs::directory_entry& entry : fs::directory_iterator(log.parent_path()))
    if (entry.path().filename().string().starts_with(prefix)) copies.push_back(entry.path());
  if (copies.empty()) return;
  std::sort(copies.begin(), copies.end());
  if (copies.size() > 1)
    throw InputError(log_path + ": " + std::to_string(copies.size()) + " recovered copies of the log are beside it (" +
                     copies.front().filename().string() + ", " + copies[1].filename().string() +
                     "...); keep the one to resume from and move the others away");
  std::string kept;
  if (fs::exists(fs::symlink_status(log))) {
    fs::path aside;
    for (int number = 1; fs::exists(fs::symlink_status(aside = set_aside_path(log, SetAside::replaced, number)));
         ++number) {}
    if (::rename(log.c_str(), aside.c_str()) != 0) throw FileError(log_path, "setting the replacement aside", errno);
    kept = "; what was at its name is kept as " + aside.string();
  }
  if (::rename(copies.front().c_str(), log.c_str()) != 0)
    throw FileError(copies.front().string(), "renaming the recovered copy to the log", errno);
  fsync_directory(log.parent_path());
  std::fprintf(stderr, "fovlab: %s: resumed from %s, the events a session kept when its log was replaced%s\n",
               log_path.c_str(), copies.front().filename().string().c_str(), kept.c_str());
}

// A session that ended but was killed before its seal was written: the seal is all that is
// missing (a torn seal line is set aside first). No trial runs.
SessionOutcome seal_finished_session(const EventLogFile& log, const SessionRecord& record, const LabKey* lab_key,
                                     SessionOutcome outcome) {
  if (log.torn_tail) set_torn_tail_aside(log);
  EventLogWriter writer(log.path, log.last_chain, static_cast<int64_t>(log.events.size()), lab_key);
  SealEvent seal;
  seal.stamp.t = record.last_time_s;
  seal.trials_complete = static_cast<int>(record.trials.size());
  writer.append(to_json(seal));
  outcome.resumed = true;
  outcome.finished = true;
  outcome.excluded = record.excluded;
  outcome.trials_completed = static_cast<int>(record.trials.size());
  outcome.events_written = 1;
  outcome.stop_reason = "the session had ended; its seal was added";
  return outcome;
}

// A participant field's value: at most 200 bytes of text without control characters.
void check_participant_field_value(const std::string& name, const std::string& value) {
  const bool control =
      std::any_of(value.begin(), value.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
  if (value.size() > 200 || control)
    throw InputError("--field " + name + ": expected at most 200 characters of text without control characters");
}

std::string join(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (const std::string& item : items) text += (text.empty() ? "" : separator) + item;
  return text;
}

// What a headset session cannot do yet (issue 42, docs/hmd.md), refused before anything is opened
// or written: the gaze resting on the rendered depth of stimuli that show no surface (volume,
// fvolume: their rays pass through a medium; the config cannot give a fixation distance beside
// rendered-depth, so they are refused rather than given one). Head-tracked views of stimuli made
// ahead for one view are refused where the config is read (study_config.cpp), for every command.
void check_headset_session_buildable(const StudyConfig& config, const StudyPlan& plan) {
  const HeadsetDisplayConfig& headset = config.display.headset;
  const std::string& path = config.source_path;
  if (headset.gaze_fixation != GazeFixation::rendered_depth) return;
  for (const PlannedStimulus& stimulus : plan.stimuli) {
    const StimulusFamily family = stimulus_family(stimulus.spec.method());
    if (family == StimulusFamily::sphere_traced) continue;
    throw InputError(path + ": display.gaze_fixation: \"rendered-depth\" rests the gaze on the surface the sphere "
                     "tracer finds, and method " + std::string(describe(stimulus.spec.method()).name) + " (" +
                     stimulus_family_name(family) +
                     ") has no such trace; set gaze_fixation = \"fixation-distance\" with fixation_distance_mm");
  }
}

// The runtime's name and version, as the header records it.
std::string openxr_runtime_name(const OpenXrSession& session) {
  XrInstanceProperties properties{XR_TYPE_INSTANCE_PROPERTIES};
  if (XR_FAILED(xrGetInstanceProperties(session.instance.handle, &properties))) return "unknown";
  return std::string(properties.runtimeName) + " " + std::to_string(XR_VERSION_MAJOR(properties.runtimeVersion)) + "." +
         std::to_string(XR_VERSION_MINOR(properties.runtimeVersion)) + "." +
         std::to_string(XR_VERSION_PATCH(properties.runtimeVersion));
}

// The head's pose (VIEW in LOCAL) as the runtime gives it: the head-tracked reference and poses.
HeadPose head_pose_of_openxr(const XrPosef& pose) {
  return {{pose.position.x, pose.position.y, pose.position.z},
          {pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w}};
}

// A head-tracked run's reference: the head in LOCAL at the last frame's predicted display time, taken
// once, when the run starts (the views are valid by then: headset_views_at_start).
HeadPose head_reference_at_start(OpenXrPresenter& headset, const StudyConfig& config) {
  const std::optional<XrPosef> pose =
      locate_head_in_local(headset.session(), headset.last_frame().predicted_display_time);
  if (!pose)
    throw InputError("openxr: the headset gave no valid head pose in its LOCAL space (is it tracked?); " +
                     config.source_path + " (display.view_model = \"head-tracked\") was not started");
  return sanitize_head_pose(head_pose_of_openxr(*pose), nullptr);
}

// The views a new headset session renders from: the config's (headset_eye_views), the ones its plan
// and its pre-rendered frames were made for, after checking them against the views the runtime
// locates in the head (frames run until it gives valid poses, at most a second): each eye's field
// of view must be the config's (check_runtime_fields_of_view); an IPD other than the config's is
// said on stderr (the study shows every participant the config's).
HeadsetViews headset_views_at_start(OpenXrPresenter& headset, const StudyConfig& config) {
  const int patience_frames = static_cast<int>(std::ceil(headset.refresh_hz()));
  for (int frame = 0; !headset.last_frame().views_valid; ++frame) {
    if (frame >= patience_frames || headset.close_requested())
      throw InputError("openxr: the headset gave no valid eye poses in " + std::to_string(patience_frames) +
                       " frames (is it tracked?); " + config.source_path + " was not started");
    headset.wait_until(headset.now_s() + 1.0 / headset.refresh_hz());
  }
  HeadsetViews views;
  views.runtime = openxr_runtime_name(headset.session());
  views.eye_width_px = static_cast<int>(headset.session().eye_width_px);
  views.eye_height_px = static_cast<int>(headset.session().eye_height_px);
  for (size_t eye = 0; eye < 2; ++eye)
    views.eyes[eye] = eye_view_from_openxr(headset.last_frame().views_in_head[eye], 1.0);  // a scene unit a metre
  check_runtime_fields_of_view(views, config);
  const double runtime_ipd_mm =
      1000.0 * std::hypot(views.eyes[1].position_in_head[0] - views.eyes[0].position_in_head[0],
                          views.eyes[1].position_in_head[1] - views.eyes[0].position_in_head[1],
                          views.eyes[1].position_in_head[2] - views.eyes[0].position_in_head[2]);
  if (std::abs(runtime_ipd_mm - config.display.headset.ipd_mm) > 0.5)
    std::fprintf(stderr, "fovlab: the headset's IPD is %.1f mm, the config's %.1f mm: the study renders with %s's\n",
                 runtime_ipd_mm, config.display.headset.ipd_mm, config.source_path.c_str());
  views.eyes = headset_eye_views(config.display.headset);
  views.view_model = config.display.headset.view_model;
  views.gaze_fixation = config.display.headset.gaze_fixation;
  views.fixation_distance_mm = config.display.headset.fixation_distance_mm;
  return views;
}

// Ctrl-C at the terminal while a headset session is paused (from its session_paused, through its
// seal, to the end of the wait for the focus): the operator ends the wait, and the run exits as a
// closed window's does, sealed (the log's last events are the pause and its seal). Installed before
// the pause is logged, so that a Ctrl-C between the pause and its seal cannot leave the log
// unsealed. At any other time Ctrl-C stops the program as it always did.
volatile std::sig_atomic_t operator_quit_requested = 0;

void note_operator_quit(int) { operator_quit_requested = 1; }

class OperatorQuitScope {
 public:
  OperatorQuitScope() {
    operator_quit_requested = 0;
    struct sigaction action {};
    action.sa_handler = &note_operator_quit;
    sigemptyset(&action.sa_mask);
    installed_ = sigaction(SIGINT, &action, &previous_) == 0;
  }
  ~OperatorQuitScope() {
    if (installed_) sigaction(SIGINT, &previous_, nullptr);
  }
  OperatorQuitScope(const OperatorQuitScope&) = delete;
  OperatorQuitScope& operator=(const OperatorQuitScope&) = delete;

 private:
  struct sigaction previous_ {};
  bool installed_ = false;
};

// A headset session paused for a lost focus or the runtime's stop (sealed): a "Paused" screen in both
// eyes while the runtime's frames run (a stopped session has none until the runtime offers READY
// again), until the focus returns (true: resume in this run) or the runtime ends the session,
// options.refocus_timeout_s pass, or the operator presses Ctrl-C (false: exit, and a later run
// resumes). The caller holds an OperatorQuitScope from before the pause was logged.
bool wait_for_refocus(OpenXrPresenter& headset, const StudyConfig& config, const SessionOptions& options) {
  if (operator_quit_requested) {
    std::fprintf(stderr, "fovlab: paused (%s); the run was ended at the terminal\n", headset.close_reason().c_str());
    return false;
  }
  if (options.refocus_timeout_s <= 0 || !headset.may_regain_focus()) return false;
  std::fprintf(stderr,
               "fovlab: paused (%s); waiting up to %.0f s for the headset to be focused again (Ctrl-C ends the "
               "run; the log is sealed, and running the same command again resumes it)\n",
               headset.close_reason().c_str(), options.refocus_timeout_s);
  const Rgba8Frame screen =
      render_text_screen(config.display.width_px, config.display.height_px,
                         "Paused: put the headset back on.\n\nThe session resumes where it stopped.");
  const bool focused =
      headset.wait_for_focus(screen, options.refocus_timeout_s, [] { return operator_quit_requested != 0; });
  std::fprintf(stderr, "fovlab: %s\n",
               focused                       ? "the headset is focused again: the session resumes"
               : operator_quit_requested     ? "the wait for the headset was ended at the terminal"
               : !headset.may_regain_focus() ? "the OpenXR runtime ended the headset session; the session stays paused"
                                             : "the headset was not focused again; the session stays paused");
  return focused;
}

}  // namespace

std::string session_log_path(const std::string& results_dir, const std::string& study, const std::string& participant) {
  return (fs::path(results_dir) / study / participant / kSessionLogName).string();
}

std::string next_participant_id(const std::string& results_dir, const std::string& study) {
  const std::map<int, std::string> folders = study_version_folders(results_dir, study);
  for (int number = 1;; ++number) {
    char id[16];
    std::snprintf(id, sizeof id, "P%03d", number);
    const bool used = fs::exists(fs::path(results_dir) / study / id) ||
                      std::any_of(folders.begin(), folders.end(), [&](const auto& folder) {
                        return fs::exists(fs::path(results_dir) / folder.second / id);
                      });
    if (!used) return id;
  }
}

SessionOutcome run_session(const StudyConfig& config, const SessionOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  check_new_participant_id(options.participant);
  const StudyPlan plan = make_study_plan(config, options.participant);
  SessionOutcome outcome;
  outcome.plan_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  outcome.trials_total = static_cast<int>(plan.trials.size());
  outcome.trials_total_is_upper_bound = !plan.tracks.empty();
  check_plan_renderable(plan, config.source_path, PlanUse::session);  // before the window, the lock, any render
  check_log_fits_readers(plan,
                         config.source_path);  // a log export, analyze and replay could not read back is not begun

  // Answers and gaze: parsed before anything is written.
  std::optional<ObserverModel> observer_model;
  if (!options.observer.empty()) observer_model = parse_observer_spec(options.observer, plan);
  // The config's [gaze] require, and in a window a gaze-contingent study's need of a named source
  // (docs/gaze.md): refused here, before any window or folder.
  const bool in_headset = config.display.kind == DisplayKind::openxr;
  if (in_headset) check_headset_session_buildable(config, plan);
  const ChosenGaze chosen_gaze = choose_gaze(config, options.gaze, options.headless);
  const GazeSpec& gaze_spec = chosen_gaze.spec;
  if (gaze_spec.kind == GazeSpec::Kind::mouse && (options.headless || in_headset))
    throw InputError(std::string("--gaze mouse: a ") + (in_headset ? "headset" : "headless") +
                     " session has no pointer (use synthetic, trace:FILE or pupil:HOST:PORT)");
  if (!observer_model && options.headless && !in_headset)
    throw InputError("--headless: a headless session has no keyboard (add --observer simulated)");

  const std::optional<LabKey> lab_key = read_optional_lab_key(options.lab_key_path, options.results_dir);
  for (const auto& [name, value] : options.participant_fields) {
    if (std::find(config.participant_fields.begin(), config.participant_fields.end(), name) ==
        config.participant_fields.end())
      throw InputError("--field " + name + ": not a participant field of " + config.source_path + " (expected " +
                       (config.participant_fields.empty() ? std::string("none: the config has no [participant] fields")
                                                          : "one of " + join(config.participant_fields, ", ")) +
                       ")");
    check_participant_field_value(name, value);
  }

  // The participant's folder is locked before anything in it is read, cut or renamed, and stays
  // locked until this run exits: a second run of the participant changes nothing and exits 2.
  check_output_target(options.results_dir, "--results", {OutputKind::folder});
  check_output_target(options.cache_dir, "--cache", {OutputKind::folder});
  if (!options.screenshots_dir.empty())
    check_output_target(options.screenshots_dir, "--screenshots", {OutputKind::folder});
  // The folder of the config's version (study/log/study_versions.h): a new participant under an
  // edited config is refused here, after every other check of the input and before anything is
  // written, unless options.new_version.
  outcome.study_folder = choose_study_folder(options.results_dir, config, options.participant, options.new_version);
  outcome.log_path = session_log_path(options.results_dir, outcome.study_folder, options.participant);
  const ParticipantLock lock(options.results_dir, outcome.study_folder, options.participant);
  test_pause_point("locked");
  restore_recovered_log(outcome.log_path);

  // An existing log: the same study and config, intact, not finished -> resume.
  std::optional<SessionRecord> record;
  std::optional<ScheduleCheck> schedule;  // a resumed log against the plan, its adaptive tracks' progress
  std::optional<EventLogFile> existing;
  if (fs::is_symlink(outcome.log_path))
    throw InputError(outcome.log_path + ": the session log is a symbolic link (expected the log itself); not resuming");
  if (fs::exists(fs::symlink_status(outcome.log_path))) existing = read_event_log(outcome.log_path);
  // A crash between creating the log and completing its header line leaves no event: the session
  // then starts afresh (a torn header line is set aside below, never used).
  if (existing && !existing->events.empty()) {
    record = read_session_record(*existing, lab_key ? &*lab_key : nullptr);
    const nlohmann::json& header = record->header;
    if (record->integrity.status == LogStatus::broken)
      throw InputError(outcome.log_path + ":" + std::to_string(record->integrity.line) + ": " +
                       record->integrity.reason + "; not resuming");
    if (existing->schema_version != log_schema_version)
      throw InputError(outcome.log_path + ":1: written by an older fovlab (log schema " +
                       std::to_string(existing->schema_version) +
                       "); finish it with that version or use another participant ID");
    if (header.value("study", "") != config.name || header.value("participant", "") != options.participant)
      throw InputError(outcome.log_path + ":1: the log belongs to study \"" + header.value("study", "") +
                       "\", participant \"" + header.value("participant", "") + "\"");
    if (header.value("config_hash", "") != config.hash)
      throw InputError(config.source_path + ": differs from the config this participant started with (" +
                       outcome.log_path + ", config_hash " + header.value("config_hash", "") +
                       "); resume with the same config or use another participant ID");
    const nlohmann::json observer = observer_model ? observer_json(*observer_model) : nlohmann::json("human");
    if (!header.contains("observer") || header["observer"] != observer)
      throw InputError(outcome.log_path + ":1: the session was started with observer " +
                       header.value("observer", nlohmann::json()).dump() + "; resume it with the same --observer");
    if (record->integrity.keyed && !lab_key)
      throw InputError(outcome.log_path + ":1: the session's seals are keyed (lab key " +
                       header.value("lab_key_id", "") + "); resume it with the same --lab-key");
    if (!record->integrity.keyed && lab_key)
      throw InputError("--lab-key: the session started without a lab key (" + outcome.log_path +
                       "); resume it without one, or use another participant ID");
    if (record->ended && record->integrity.status == LogStatus::sealed)
      throw InputError(outcome.log_path + ": participant \"" + options.participant +
                       "\" already finished this study (" + record->end_reason + "); choose another participant ID");
    if (header.value("scene_hashes", nlohmann::json()) != scene_hashes(plan, plan_image_hashes(plan)))
      throw InputError(outcome.log_path +
                       ":1: a scene file changed since this participant started (scene_hashes); "
                       "restore it to resume, or use another participant ID");
    schedule = check_trials_against_plan(*record, plan, outcome.log_path);
    // Ended, but killed before its seal: every check above passed, so the seal is all it lacks.
    if (record->ended) return seal_finished_session(*existing, *record, lab_key ? &*lab_key : nullptr, outcome);
    outcome.resumed = true;
  }

  // The [participant] fields of a new session: given, asked, or (a simulated observer) left empty.
  // A resumed session keeps its header's and asks nothing.
  std::map<std::string, std::string> participant_fields;
  if (record) {
    for (const auto& [name, value] : options.participant_fields) {
      const nlohmann::json& logged = record->header.value("participant_fields", nlohmann::json::object());
      if (!logged.contains(name) || logged[name] != value)
        throw InputError("--field " + name + "=" + value + ": the session was started with " + name + " = " +
                         (logged.contains(name) ? logged[name].dump() : std::string("none")) + " (" + outcome.log_path +
                         "); resume it without --field or with the same value");
    }
  } else {
    participant_fields = options.participant_fields;
    for (const std::string& name : config.participant_fields) {
      if (participant_fields.count(name)) continue;
      if (options.ask_participant_field) {
        participant_fields[name] = options.ask_participant_field(name);
        check_participant_field_value(name, participant_fields[name]);
      } else if (observer_model) {
        participant_fields[name] = "";
      } else {
        throw InputError(config.source_path + ": [participant] fields: give " + name + " with --field " + name +
                         "=VALUE (or run on a terminal to be asked)");
      }
    }
  }

  // Everything that can fail on the user's input comes before the first write: gaze source (a
  // trace file, the tracker's address), the window and its font, the scenes' compilation.
  // --present-device naming the rendering device's own selector is no second device.
  const bool own_present_device =
      !options.present_device_selector.empty() && options.present_device_selector != options.device_selector;
  std::unique_ptr<Presenter> presenter;
  OpenXrPresenter* headset = nullptr;
  std::optional<HeadsetViews> headset_views;
  std::optional<HeadPose> head_reference;  // head-tracked: this run's (the head in LOCAL as it starts)
  if (in_headset) {
    OpenXrPresenterOptions headset_options;
    headset_options.session.eye_width_px = static_cast<uint32_t>(config.display.headset.eye_width_px);
    headset_options.session.eye_height_px = static_cast<uint32_t>(config.display.headset.eye_height_px);
    headset_options.session.validation = options.validation;
    if (options.mirror_window) {
      // 1:1 with the eye's pixels (the compose only scales up, by whole factors).
      WindowPresenterOptions mirror;
      mirror.width_px = config.display.headset.eye_width_px;
      mirror.height_px = config.display.headset.eye_height_px;
      mirror.title = "fovlab mirror (left eye): " + config.name;
      mirror.validation = options.validation;
      mirror.screenshots = false;
      headset_options.mirror_window = mirror;
    }
    auto opened = std::make_unique<OpenXrPresenter>(headset_options);
    headset = opened.get();
    presenter = std::move(opened);
    find_font_path();
    if (std::abs(headset->refresh_hz() - config.display.refresh_hz) > 0.01 * config.display.refresh_hz)
      throw InputError(config.source_path + ": display.refresh_hz is " + std::to_string(config.display.refresh_hz) +
                       " but the headset runs at " + std::to_string(headset->refresh_hz()) +
                       " Hz (stimulus durations would be wrong); set the config to match");
    // A resumed session keeps the views it started with (its header's), so that all its frames, and
    // its replay, are rendered alike; a new one takes the runtime's, made for the config's angles.
    if (record) {
      headset_views =
          headset_views_from_json(record->header.value("headset", nlohmann::json()), outcome.log_path + ":1");
      if (headset_views->eye_width_px != static_cast<int>(headset->session().eye_width_px) ||
          headset_views->eye_height_px != static_cast<int>(headset->session().eye_height_px))
        throw InputError(outcome.log_path + ":1: headset: the session started with eyes of " +
                         std::to_string(headset_views->eye_width_px) + "x" +
                         std::to_string(headset_views->eye_height_px) + " pixels, the headset now gives " +
                         std::to_string(headset->session().eye_width_px) + "x" +
                         std::to_string(headset->session().eye_height_px) + "; not resuming");
    } else {
      headset_views = headset_views_at_start(*headset, config);
    }
    // Not refused: the config fixes the size for every participant, and the compositor resamples.
    const OpenXrSession& eyes = headset->session();
    if (eyes.eye_width_px != eyes.recommended_eye_width_px || eyes.eye_height_px != eyes.recommended_eye_height_px)
      std::fprintf(stderr,
                   "fovlab: each eye renders at %ux%u px (the config's); the runtime %s recommends %ux%u px, "
                   "so its compositor resamples each eye's image\n",
                   eyes.eye_width_px, eyes.eye_height_px, headset_views->runtime.c_str(), eyes.recommended_eye_width_px,
                   eyes.recommended_eye_height_px);
    // Head-tracked: each run's own reference, where the head is as it starts (a resumed run's LOCAL
    // space is the runtime's anew); the header records the first run's.
    if (headset_views->view_model == HeadsetViewModel::head_tracked) {
      head_reference = head_reference_at_start(*headset, config);
      if (!record) headset_views->head_reference = head_reference;
    }
  } else if (options.headless) {
    presenter = std::make_unique<HeadlessPresenter>(config.display.refresh_hz);
    if (!options.screenshots_dir.empty()) find_font_path();  // headless screenshots draw the text screens
  } else {
    WindowPresenterOptions window;
    window.width_px = config.display.width_px;
    window.height_px = config.display.height_px;
    window.fullscreen = config.display.fullscreen;
    window.title = "fovlab: " + config.name;
    window.screenshots = !options.screenshots_dir.empty();
    window.validation = options.validation;
    window.device_selector = own_present_device ? options.present_device_selector : options.device_selector;
    window.device_flag = own_present_device ? "--present-device" : "--device";
    presenter = std::make_unique<WindowPresenter>(window);
    find_font_path();  // the text screens' font: missing -> an error naming the package, now
    const double measured_hz = presenter->refresh_hz();
    if (std::abs(measured_hz - config.display.refresh_hz) > 0.01 * config.display.refresh_hz)
      throw InputError(config.source_path + ": display.refresh_hz is " + std::to_string(config.display.refresh_hz) +
                       " but the monitor runs at " + std::to_string(measured_hz) +
                       " Hz (stimulus durations would be wrong); set the monitor or the config to match");
  }
  // The session clock continues a resumed log's last time; a tracker's clock is mapped onto it.
  const double time_base_s = record ? record->last_time_s : 0.0;
  std::unique_ptr<GazeSource> gaze;
  if (gaze_spec.kind == GazeSpec::Kind::mouse) {
    gaze = std::make_unique<MouseGazeSource>(*presenter);
  } else if (gaze_spec.kind == GazeSpec::Kind::openxr) {
    if (!headset->input().has_eye_gaze())
      throw InputError(config.source_path + ": the headset gives no eye gaze (its runtime " + headset_views->runtime +
                       " has no XR_EXT_eye_gaze_interaction, or its system no eye tracker); give --gaze synthetic or "
                       "--gaze trace:FILE (docs/gaze.md)");
    gaze = std::make_unique<OpenXrGazeSource>(*headset, headset_gaze_geometry(*headset_views), time_base_s);
  } else
    gaze = make_gaze_source(gaze_spec, config.display.width_px, config.display.height_px, plan.session_seed,
                            [&presenter, time_base_s] { return time_base_s + presenter->now_s(); });

  // One device renders and presents unless --present-device names another (or, chosen
  // automatically, the preferred rendering device cannot present to the window).
  // A headset renders on the device its runtime chose (XR_KHR_vulkan_enable2).
  auto* window = dynamic_cast<WindowPresenter*>(presenter.get());
  std::unique_ptr<vk::Context> render_context;
  if (!headset && (!window || own_present_device ||
                   (options.device_selector.empty() && !vk::is_preferred_device(window->context().description)))) {
    render_context = std::make_unique<vk::Context>(vk::ContextOptions{options.device_selector, options.validation});
  }
  vk::Context& context = headset ? headset->context() : render_context ? *render_context : window->context();
  outcome.frame_path = headset ? "on_device" : !window ? "none" : render_context ? "via_host" : "on_device";
  if (outcome.frame_path == "via_host")
    std::fprintf(stderr, "fovlab: rendering on '%s', presenting on '%s': frames are copied through the host\n",
                 context.description.name.c_str(), window->device_name().c_str());
  // In a headset, one library an eye, each rendering every stimulus from its eye's view.
  const bool head_tracked = head_reference.has_value();
  StimulusLibrary library(context, options.cache_dir,
                          headset_views ? std::optional<EyeView>(headset_views->eyes[0]) : std::nullopt, head_tracked);
  std::optional<StimulusLibrary> right_library;
  if (headset_views) right_library.emplace(context, options.cache_dir, headset_views->eyes[1], head_tracked);
  std::vector<std::pair<int, StimulusSpec>> all;
  for (size_t id = 0; id < plan.stimuli.size(); ++id) all.emplace_back(static_cast<int>(id), plan.stimuli[id].spec);
  // Scene errors surface here, before any event is written.
  if (!right_library) {
    outcome.prepare_s = library.prepare(all, options.prepare_progress);
  } else {
    const auto half = [&](double offset) {
      return [&, offset](double share) {
        if (options.prepare_progress) options.prepare_progress(offset + 0.5 * share);
      };
    };
    outcome.prepare_s = library.prepare(all, half(0.0)) + right_library->prepare(all, half(0.5));
  }
  test_pause_point("prepared");
  // The images the library holds are what the participant sees: a resumed session shows those the
  // log recorded (an image changed between the check above and their reading is refused here), and a
  // new one records the hashes of the very bytes it read.
  const nlohmann::json shown_images = library.image_hashes();
  if (record)
    check_image_hashes(record->header.value("image_hashes", nlohmann::json::object()), shown_images,
                       outcome.log_path + ":1: image_hashes");
  std::unique_ptr<ResponseSource> responses;
  if (observer_model) responses = std::make_unique<ObserverResponses>(*observer_model, plan);
  else responses = std::make_unique<KeyResponses>(config.protocol.question);

  std::string torn_aside;
  if (existing && existing->torn_tail) {
    torn_aside = set_torn_tail_aside(*existing);
    std::fprintf(stderr, "fovlab: %s: the last line was cut off by a crash (%zu bytes); set aside in %s\n",
                 outcome.log_path.c_str(), existing->torn_tail->size(), torn_aside.c_str());
  }
  // The header before the log file exists: an error making it (a scene file gone) leaves no empty log.
  std::optional<SessionHeaderEvent> header;
  if (!record) {
    SessionHeaderInputs inputs{
        &plan,
        &context.description,
        observer_model ? &*observer_model : nullptr,
        headset                    ? "openxr"
        : presenter->is_headless() ? "headless"
                                   : (config.display.fullscreen ? "fullscreen" : "window"),
        window ? window->device_name() : "",
        outcome.frame_path,
        gaze->describe(),
        gaze_source_json(source_kind(gaze_spec), gaze->describe(), chosen_gaze.requested, config.gaze),
        presenter->refresh_hz(),
        utc_now(),
        participant_fields,
        shown_images};
    header = make_session_header(inputs);
    if (lab_key) header->lab_key_id = lab_key->id;
    if (headset_views) header->headset = headset_views_json(*headset_views);
    // Schema 12: whether stimulus events count late frames (the runtime converts CLOCK_MONOTONIC).
    if (headset) header->headset[log_keys::late_frames_measured] = headset->measures_late_frames();
  }
  EventLogWriter writer(outcome.log_path, record ? existing->last_chain : std::string(),
                        record ? static_cast<int64_t>(existing->events.size()) : 0, lab_key ? &*lab_key : nullptr);
  std::optional<RightEyeStimuli> right_eye;
  if (right_library)
    right_eye =
        RightEyeStimuli{&*right_library, headset_gaze_geometry(*headset_views), headset_views->gaze_fixation, {}};
  if (right_eye && head_tracked)
    right_eye->head_pose = [headset, reference = *head_reference]() -> std::optional<HeadPose> {
      // Where the runtime predicts the head at the coming frame's display time (the last one's plus a period).
      const std::optional<XrPosef> pose = locate_head_in_local(headset->session(), headset->next_display_time());
      if (!pose) return std::nullopt;
      return head_pose_relative_to(reference, head_pose_of_openxr(*pose));
    };
  if (right_eye && head_tracked)
    right_eye->eyes_in_world = [reference = *head_reference, eyes = headset_views->eyes](const HeadPose& head) {
      std::array<ViewPose, 2> poses;
      for (size_t eye = 0; eye < 2; ++eye) {
        const EyeView in_local = eye_view_in_reference_space(eyes[eye], head, reference);
        poses[eye] = ViewPose{in_local.position_in_head, in_local.orientation_in_head};
      }
      return poses;
    };
  // A run of trials from where the log says the session stands: this process's first, and in a
  // headset each one after the focus came back (resumed as a rerun would resume it).
  std::optional<SessionRun> run;
  const auto start_run = [&] {
    run.emplace(plan, options, *presenter, *gaze, *responses, library, writer, time_base_s,
                right_eye ? &*right_eye : nullptr);
  };
  const auto count_run = [&] {  // what a finished run of trials did, into this process's outcome
    outcome.events_written += run->events_written();
    outcome.gaze_age_s.insert(outcome.gaze_age_s.end(), run->gaze_age_s().begin(), run->gaze_age_s().end());
    outcome.dropped_frames += run->dropped_frames();
    if (run->late_frames()) outcome.late_frames = outcome.late_frames.value_or(0) + *run->late_frames();
  };
  const auto log_resumed = [&] {
    SessionResumedEvent resumed;
    resumed.next_trial = schedule->next_trial;
    resumed.started_utc = utc_now();
    resumed.gaze = gaze->describe();
    resumed.gaze_source =
        gaze_source_json(source_kind(gaze_spec), gaze->describe(), chosen_gaze.requested, config.gaze);
    if (record->incomplete_trial >= 0) resumed.discarded_trial = record->incomplete_trial;
    if (!torn_aside.empty()) resumed.torn_line_set_aside = torn_aside;
    run->log(to_json(resumed));
  };
  start_run();
  if (header) {
    run->log(to_json(*header));
  } else {
    log_resumed();
  }
  if (record) run->set_excluded_logged(record->excluded);
  const auto loop_start = std::chrono::steady_clock::now();
  if (!schedule) schedule.emplace(plan);
  int complete_before = record ? static_cast<int>(record->trials.size()) : 0;
  for (;;) {
    std::optional<OperatorQuitScope> operator_quit;  // a headset's pause, until its wait ends
    try {
      const bool kept = run->run_trials(schedule->next_trial, record ? record->attention_errors : 0, record.has_value(),
                                        complete_before, schedule->progress);
      outcome.finished = true;
      outcome.excluded = !kept;
    } catch (const SessionAborted& aborted) {
      if (headset) operator_quit.emplace();
      outcome.stop_reason = aborted.reason;
      run->log(to_json(SessionPausedEvent{{}, aborted.reason}));
    }
    outcome.trials_run += run->trials_completed();
    outcome.trials_completed = complete_before + run->trials_completed();
    // The end of this run, sealed: the complete trials and the chain so far (keyed with a lab key).
    run->log(to_json(SealEvent{{}, outcome.trials_completed, {}}));
    // A headset that lost the focus while its runtime still runs it may get it back: the paused,
    // sealed session then resumes in this process as `fovlab run` again would, from the log.
    if (outcome.finished || !headset || !headset->close_requested() || !wait_for_refocus(*headset, config, options))
      break;
    existing = read_event_log(outcome.log_path);
    record = read_session_record(*existing, lab_key ? &*lab_key : nullptr);
    if (record->integrity.status == LogStatus::broken)
      throw InputError(outcome.log_path + ":" + std::to_string(record->integrity.line) + ": " +
                       record->integrity.reason + "; not resuming");
    schedule = check_trials_against_plan(*record, plan, outcome.log_path);
    complete_before = static_cast<int>(record->trials.size());
    torn_aside.clear();
    outcome.stop_reason.clear();
    ++outcome.focus_pauses_resumed;
    count_run();
    start_run();
    log_resumed();
    run->set_excluded_logged(record->excluded);
  }
  outcome.trial_loop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
  if (window && render_context && window->validation_message_count() > 0)
    throw std::runtime_error("the Vulkan validation layer reported " +
                             std::to_string(window->validation_message_count()) +
                             " message(s) in the session window (see stderr)");
  if (window) {
    outcome.cross_device_frames = window->cross_device_copies().frames;
    outcome.cross_device_copy_s = window->cross_device_copies().seconds;
  }
  count_run();
  outcome.present_clock = presenter->present_clock();
  outcome.log_write_s = writer.seconds_writing();
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (context.validation_message_count() > 0)
    throw std::runtime_error("the Vulkan validation layer reported " +
                             std::to_string(context.validation_message_count()) + " message(s) (see stderr)");
  return outcome;
}

}  // namespace fovlab
