// fovlab analyze: per-study thresholds from session logs (analysis/study), written as JSON, CSV,
// SVG and one HTML report (analysis/report).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "analysis/report/report.h"
#include "analysis/study/headline.h"
#include "analysis/study/study_analysis.h"
#include "app/commands.h"
#include "study/log/study_versions.h"
#include "app/output_options.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "study/log/log_integrity.h"
#include "study/config/study_config.h"

namespace fovlab::app {
namespace {

namespace fs = std::filesystem;

struct AnalyzeArguments {
  std::vector<std::string> inputs;
  std::string out;
  std::string alternative = "two-sided";
  double alpha = 0.05;
  std::optional<double> guess_rate;  // none: by protocol
  int bootstrap = 1000;
  uint64_t seed = 1;
  double rating_cutoff = 2.0;
  bool include_broken = false;
  std::string observers;     // "": refuse a mix of human and simulated sessions
  std::string gaze_sources;  // "": a gaze-contingent study's mouse sessions kept apart from the others
  std::string lab_key_path;
  bool force = false;  // replace an earlier analysis at the output folder
};

// results/<study>/analysis: beside the participants when one study folder is given, else under
// ./results. The study name comes from a log header: the reader (analysis/study) leaves out logs
// whose name could not name a folder, and it is checked again here before it becomes a path.
std::string default_out_dir(const std::vector<std::string>& inputs, const analysis::StudyData& data) {
  const std::string& study = data.study;
  if (!is_valid_study_name(study))
    throw InputError((data.participants.empty() ? std::string("a session log") : data.participants.front().log_path) +
                     ": line 1: study: expected a name that is one folder, got \"" + study + "\"");
  // A later config version analysed, its logs all in its own folder: beside them, never in
  // results/<study>/analysis, which is the first version's.
  for (const analysis::ConfigVersion& version : data.config_versions) {
    if (!version.analysed || version.folders.size() != 1) continue;
    const std::optional<int> number =
        study_version_of_folder_name(study, fs::path(version.folders.front()).filename().string());
    if (number && *number > 1) return (fs::path(version.folders.front()) / "analysis").string();
  }
  if (inputs.size() == 1 && fs::is_directory(inputs.front())) {
    const fs::path folder = fs::path(inputs.front()).lexically_normal();
    const fs::path named = folder.filename().empty() ? folder.parent_path() : folder;
    // results/<study>, or a later config version's results/<study>@vN (study/log/study_versions.h).
    if (study_version_of_folder_name(study, named.filename().string())) return (named / "analysis").string();
    if (fs::is_directory(folder / study)) return (folder / study / "analysis").string();
  }
  return (fs::path("results") / study / "analysis").string();
}

// Ye et al. 2022, 4.4.1: per block (and pooled), the grid of mean scores over every level, rows from the
// largest y down, the best pair starred.
void print_rating_grid(const analysis::RatingGrid& grid) {
  std::printf(
      "pilot grid (Ye et al. 2022, 4.4.1): mean score (3 identical, 1 significant difference) per %s (columns) and %s "
      "(rows) over every level: each participant's mean, then the mean over participants; * the best\n",
      grid.x_key.c_str(), grid.y_key.c_str());
  const size_t columns = grid.x_values.size();
  for (const analysis::GridMap& map : grid.maps) {
    if (map.level) continue;
    std::string best;
    for (size_t index : map.best)
      best += (best.empty() ? "" : " and ") + std::string("(") + format_number(map.cells[index].x, 6) + ", " +
              format_number(map.cells[index].y, 6) + ")";
    if (map.best.empty()) {
      std::printf("  %-24s no answered trial\n", map.scene.c_str());
      continue;
    }
    std::printf("  %-24s best (%s, %s) %s: mean %s%s\n", map.scene.c_str(), grid.x_key.c_str(), grid.y_key.c_str(),
                best.c_str(), format_number(*map.cells[map.best.front()].mean_score, 4).c_str(),
                map.best.size() > 1 ? " (a tie)" : "");
    std::printf("    %8s", "y \\ x");
    for (double x : grid.x_values) std::printf(" %7s", format_number(x, 4).c_str());
    std::printf("\n");
    for (size_t row = grid.y_values.size(); row-- > 0;) {
      std::printf("    %8s", format_number(grid.y_values[row], 4).c_str());
      for (size_t column = 0; column < columns; ++column) {
        const size_t index = row * columns + column;
        const analysis::GridCell& cell = map.cells[index];
        const bool starred = std::find(map.best.begin(), map.best.end(), index) != map.best.end();
        std::string text = cell.mean_score ? format_number(*cell.mean_score, 3) : "-";
        std::printf(" %6s%s", text.c_str(), starred ? "*" : " ");
      }
      std::printf("\n");
    }
  }
}

// Ye et al. 2022, Table 2: the votes for the reference, one-sided whatever --alternative says.
void print_preference_table(const std::vector<analysis::PreferenceRow>& rows) {
  std::printf(
      "preference table (Ye et al. 2022, Table 2): votes for the reference; exact binomial, ONE-sided (greater: the "
      "reference preferred), H0 1/2, whatever --alternative says; 95 %% Clopper-Pearson\n");
  std::printf("  %-24s %-16s %-24s %9s %7s %10s %5s  %s\n", "scene", "condition", "reference v. test", "votes", "share",
              "p", "stars", "95 % CI");
  for (const analysis::PreferenceRow& row : rows) {
    const std::string group = row.group.label();
    const std::string versus = row.reference_method + " v. " + row.test_method;
    const std::string votes = std::to_string(row.reference_votes) + "/" + std::to_string(row.n);
    std::printf("  %-24s %-16s %-24s %9s %5.1f %% %10s %5s  [%.3f, %.3f]\n", group.c_str(), row.condition.c_str(),
                versus.c_str(), votes.c_str(), 100.0 * row.share, format_number(row.p_value, 4).c_str(),
                row.stars.c_str(), row.interval.lower, row.interval.upper);
  }
}

// The one number per group first (headline.csv, thresholds.json), then everything behind it.
void print_headlines(const analysis::AnalysisResult& result) {
  if (result.headlines.empty()) return;
  std::printf("headline (one per group; headline.csv; docs/analysis.md, \"The headline\"):\n");
  for (const analysis::Headline& headline : result.headlines) {
    std::string figure;
    if (headline.value)
      figure = headline.quantity + " " + format_number(*headline.value, 4) +
               (headline.lower ? " " + format_interval(*headline.lower, *headline.upper, 4) : std::string());
    else figure = headline.quantity + ": none";
    const bool estimated = headline.status == analysis::HeadlineStatus::estimated;
    std::printf(
        "  %-24s %s%s%s\n", headline.group.label().c_str(), figure.c_str(), estimated ? "" : "  [",
        estimated
            ? ""
            : (std::string(analysis::headline_status_name(headline.status)) + ": " + headline.reason + "]").c_str());
    std::printf("    method: %s; aims at %s\n", headline.method.c_str(), headline.aims_at.c_str());
    if (headline.pooled_fit)
      std::printf("    pooled fit of every adaptive trial: %s %s\n", format_number(*headline.pooled_fit, 4).c_str(),
                  format_interval(*headline.pooled_fit_lower, *headline.pooled_fit_upper, 4).c_str());
    if (!headline.paper_rule.empty() && !headline.paper_rule_is_headline)
      std::printf("    paper's rule (%s): %s%s\n", headline.paper_rule.c_str(),
                  headline.paper_value ? format_number(*headline.paper_value, 4).c_str() : "no value",
                  headline.paper_difference.empty() ? "" : ("; " + headline.paper_difference).c_str());
    for (const std::string& flag : headline.flags) std::printf("    flag: %s\n", flag.c_str());
    for (const std::string& note : headline.notes) std::printf("    note: %s\n", note.c_str());
  }
}

void print_summary(const analysis::AnalysisResult& result, const std::string& gaze_note) {
  int excluded = 0;
  for (const auto& participant : result.participants) excluded += participant.excluded ? 1 : 0;
  const std::string observers = result.observers == "human" ? "" : " (" + result.observers + " observers)";
  // Ramps and sliders have no binomial tests: their thresholds are per participant.
  const bool per_condition = result.protocol != ProtocolKind::ramp && result.protocol != ProtocolKind::slider;
  const std::string test = per_condition ? "; test: exact binomial, " +
                                               std::string(analysis::alternative_name(result.alternative)) +
                                               ", H0 1/2, Holm, alpha " + format_number(result.alpha, 6)
                                         : "; thresholds per participant, then their mean";
  std::printf("study %s (%s%s): %zu participant(s)%s%s, %d excluded%s\n", result.study.c_str(),
              result.rules().name.data(),
              result.rules().question_name.empty() ? "" : (" " + std::string(result.rules().question_name)).c_str(),
              result.participants.size(), observers.c_str(), gaze_note.empty() ? "" : (" (" + gaze_note + ")").c_str(),
              excluded, test.c_str());
  if (result.config_versions.size() > 1)
    std::printf("config versions found: %zu, one analysed\n", result.config_versions.size());
  for (const auto& version : result.config_versions)
    std::printf("  config %s\n", analysis::describe_config_version(version).c_str());
  print_headlines(result);
  // The paper's rules, each named once (a pair study has two: pooled and per participant).
  std::string rule_named;
  for (const auto& threshold : result.thresholds) {
    const std::string rule = threshold.definition.substr(0, threshold.definition.find(':'));
    if (rule != rule_named) std::printf("the paper's rule (%s), per group:\n", (rule_named = rule).c_str());
    std::printf("  threshold %-24s %s", threshold.group.label().c_str(),
                threshold.level ? format_number(*threshold.level, 6).c_str() : "none");
    if (threshold.mean)
      std::printf(
          " %s(mean of %d participants, SD %s)",
          threshold.mean_lower ? (format_interval(*threshold.mean_lower, *threshold.mean_upper, 4) + " ").c_str() : "",
          threshold.participants_with_threshold, threshold.sd ? format_number(*threshold.sd, 4).c_str() : "-");
    else if (result.protocol == ProtocolKind::pair) std::printf(" (pooled over participants)");
    std::printf("\n");
    if (!threshold.note.empty()) std::printf("    %s\n", threshold.note.c_str());
  }
  for (const auto& group : result.fits)
    for (const auto& fit : group.fits) {
      const auto [low, high] = std::minmax_element(group.data.begin(), group.data.end(),
                                                   [](const auto& a, const auto& b) { return a.level < b.level; });
      const std::string not_estimable = analysis::fit_not_estimable_reason(fit, low->level, high->level);
      if (not_estimable.empty())
        std::printf("  fit %-10s %-18s threshold %s %s\n", group.group.label().c_str(), shape_name(fit.model.shape),
                    format_number(fit.model.parameters.threshold, 5).c_str(),
                    format_interval(fit.threshold_interval.lower, fit.threshold_interval.upper, 5).c_str());
      else
        std::printf("  fit %-10s %-18s threshold not estimable: %s\n", group.group.label().c_str(),
                    shape_name(fit.model.shape), not_estimable.c_str());
      if (!fit.note.empty()) std::printf("    fit note: %s\n", fit.note.c_str());
    }
  if (const analysis::FrameIntervalSummary& frames = result.frame_intervals; frames.intervals > 0)
    std::printf(
        "frame intervals (every session's presented refreshes pooled; report.html has each): median %s ms, SD %s ms, "
        "p99 %s ms, max %s ms, %llu of %llu late (beyond 1.5 refresh periods)\n",
        format_number(frames.median_ms.value_or(NAN), 4).c_str(), format_number(frames.sd_ms.value_or(NAN), 3).c_str(),
        format_number(frames.p99_ms.value_or(NAN), 4).c_str(), format_number(frames.max_ms.value_or(NAN), 4).c_str(),
        static_cast<unsigned long long>(frames.late), static_cast<unsigned long long>(frames.intervals));
  // Adaptive tracks: at most 20 lines (adaptive_tracks.csv holds every one).
  size_t tracks_printed = 0, tracks = 0;
  for (const auto& participant : result.participants)
    for (const auto& track : participant.tracks) {
      if (tracks++ == 0) std::printf("adaptive tracks (threshold by each procedure's rule; adaptive_tracks.csv):\n");
      if (tracks_printed >= 20) continue;
      ++tracks_printed;
      const std::string procedure =
          track.procedure + (track.start_level ? " from " + format_number(*track.start_level, 4) : std::string());
      std::printf("  %-10s %-12s %-16s %-10s %s%s, %zu trials%s\n", participant.participant.c_str(),
                  track.block.c_str(), procedure.c_str(), track.variant.empty() ? "-" : track.variant.c_str(),
                  track.threshold ? format_number(*track.threshold, 5).c_str() : "none",
                  track.threshold_lower
                      ? (" " + format_interval(*track.threshold_lower, *track.threshold_upper, 4)).c_str()
                      : "",
                  track.levels.size(), track.note.empty() ? "" : ("; " + track.note).c_str());
    }
  if (tracks > tracks_printed) std::printf("  ... and %zu more\n", tracks - tracks_printed);
  if (result.rating_grid) print_rating_grid(*result.rating_grid);
  if (!result.preferences.empty()) print_preference_table(result.preferences);
  std::vector<const analysis::ParticipantRow*> unsealed;
  for (const auto& participant : result.participants)
    if (participant.log_status != LogStatus::sealed) unsealed.push_back(&participant);
  if (!unsealed.empty()) {
    std::printf("analysed, but not sealed (%zu):\n", unsealed.size());
    for (const auto* participant : unsealed)
      std::printf("  %s: %s\n", participant->log_path.c_str(), participant->log_note.c_str());
  }
  // Keyed logs read without --lab-key: sealed, but what only the key proves is unproven.
  std::vector<const analysis::ParticipantRow*> unchecked;
  for (const auto& participant : result.participants)
    if (participant.log_status == LogStatus::sealed && !participant.log_note.empty()) unchecked.push_back(&participant);
  if (!unchecked.empty()) {
    std::printf("analysed, sealed, keyed, %s (%zu):\n", macs_not_checked_note, unchecked.size());
    for (const auto* participant : unchecked)
      std::printf("  %s: %s\n", participant->log_path.c_str(), participant->log_note.c_str());
  }
  if (!result.left_out.empty()) {
    std::printf("left out (%zu):\n", result.left_out.size());
    for (const auto& item : result.left_out) std::printf("  %s: %s\n", item.what.c_str(), item.reason.c_str());
  }
}

void analyze(const AnalyzeArguments& arguments) {
  analysis::AnalysisOptions options;
  options.alternative = analysis::parse_alternative(arguments.alternative);
  if (!(arguments.alpha > 0.0 && arguments.alpha < 1.0)) throw InputError("--alpha: expected a number in (0, 1)");
  options.alpha = arguments.alpha;
  if (arguments.guess_rate) {
    if (!(*arguments.guess_rate >= 0.0 && *arguments.guess_rate < 1.0))
      throw InputError("--guess-rate: expected a number in [0, 1)");
    options.guess_rate = arguments.guess_rate;
  }
  if (!(arguments.bootstrap >= 0 && arguments.bootstrap <= 1000000))
    throw InputError("--bootstrap: expected a whole number of replicates in [0, 1000000]");
  options.bootstrap_samples = arguments.bootstrap;
  options.seed = arguments.seed;
  if (!(arguments.rating_cutoff >= 1.0 && arguments.rating_cutoff <= 3.0))
    throw InputError("--rating-cutoff: expected a mean score in [1, 3]");
  options.rating_cutoff = arguments.rating_cutoff;
  analysis::ObserverFilter observers = analysis::ObserverFilter::unmixed;
  if (!arguments.observers.empty()) {
    const auto parsed = analysis::parse_observer_filter(arguments.observers);
    if (!parsed) throw InputError("--observers: expected human, simulated or all, got \"" + arguments.observers + "\"");
    observers = *parsed;
  }
  const std::optional<LabKey> lab_key = read_optional_lab_key(arguments.lab_key_path);
  analysis::GazeSourceFilter gaze_sources;
  if (!arguments.gaze_sources.empty()) gaze_sources = analysis::parse_gaze_source_filter(arguments.gaze_sources);
  const analysis::StudyData data = analysis::load_study(
      arguments.inputs,
      analysis::LoadOptions{lab_key ? &*lab_key : nullptr, arguments.include_broken, observers, gaze_sources});
  const std::string out = arguments.out.empty() ? default_out_dir(arguments.inputs, data) : arguments.out;
  check_output_target(out, arguments.out.empty() ? "" : "--out", {OutputKind::folder});
  analysis::check_analysis_destination(out, arguments.force);  // before the fits (which take a while)
  const analysis::AnalysisResult result = analysis::analyse_study(data, options);
  const std::vector<std::string> written = analysis::write_analysis_folder(result, out, arguments.force);
  print_summary(result, data.gaze_note);
  std::printf("wrote %zu file(s) to %s (report: %s)\n", written.size(), out.c_str(),
              (fs::path(out) / "report.html").string().c_str());
}

}  // namespace

void add_analyze_command(CLI::App& app) {
  auto arguments = std::make_shared<AnalyzeArguments>();
  CLI::App* command =
      app.add_subcommand("analyze", "Thresholds, tests, fits, tables and plots from a study's session logs");
  command->add_option("logs", arguments->inputs, "Session logs and/or results folders (every events.jsonl under them)")
      ->required();
  add_output_option(*command, "--out", arguments->out, "Output folder (default: results/<study>/analysis)",
                    {{OutputKind::folder},
                     "an earlier analysis there is replaced only with --force; a folder holding anything else never"});
  command->add_flag("--force", arguments->force, "Replace an earlier analysis in the output folder");
  command->add_option("--alternative", arguments->alternative,
                      "two-sided (default), greater or less: the binomial tests' alternative");
  command->add_option("--alpha", arguments->alpha, "Significance level of the threshold criteria (default 0.05)");
  command->add_option("--guess-rate", arguments->guess_rate,
                      "Fixed guess rate of the psychometric fits (default: 1/2 for 2afc 'better', else the "
                      "attention-check false-alarm rate)");
  command->add_option("--bootstrap", arguments->bootstrap,
                      "Parametric bootstrap replicates per fit (default 1000; 0: none)");
  command->add_option("--seed", arguments->seed, "Seed of the bootstrap, a whole number in [0, 2^64) (default 1)")
      ->check(CLI::Validator(
          [](std::string& text) {
            return text.find_first_not_of("0123456789") == std::string::npos && !text.empty()
                       ? std::string()
                       : "expected a whole number in [0, 2^64), got \"" + text + "\"";
          },
          "SEED"));
  command->add_option("--rating-cutoff", arguments->rating_cutoff,
                      "Rating studies: the lowest acceptable mean score (default 2.0)");
  command->add_flag("--include-broken", arguments->include_broken,
                    "Analyse logs whose chain or seal is broken too (left out by default)");
  command->add_option("--lab-key", arguments->lab_key_path,
                      "The lab key the sessions ran with: verify their seals' MACs");
  command
      ->add_option("--observers", arguments->observers,
                   "human, simulated or all: whose sessions to analyse (default: all of one kind; a study mixing "
                   "real participants and simulated observers is refused)")
      ->check(CLI::IsMember({"human", "simulated", "all"}));
  command->add_option(
      "--gaze-sources", arguments->gaze_sources,
      "all, or gaze source kinds separated by commas (tracker, trace, synthetic, mouse): whose sessions to "
      "analyse by their gaze (default: a gaze-contingent study's sessions with the mouse as gaze, "
      "rehearsals, are left out when others had gaze from elsewhere; docs/analysis.md)");
  command->callback([arguments] { analyze(*arguments); });
}

}  // namespace fovlab::app
