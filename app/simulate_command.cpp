// fovlab simulate: simulated participants through a study's procedures (bench/procedure_simulation.h),
// and fovlab bench-quest: the time QUEST+ takes to choose a level at a given grid size.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/output_options.h"
#include "bench/procedure_simulation.h"
#include "core/atomic_file.h"
#include "core/input_error.h"
#include "core/number_text.h"
#include "protocols/stimuli/stimulus_settings.h"
#include "study/config/study_config.h"
#include "study/schedule/quest_plus.h"

namespace fovlab::app {
namespace {

std::string cell(double value, int digits = 4) { return std::isfinite(value) ? format_number(value, digits) : "-"; }

void simulate(const std::string& config_path, const bench::SimulationOptions& options, const std::string& json_path) {
  const StudyConfig config = parse_study_config_file(config_path, renderer_scene_catalog());
  const bench::SimulationResult result = bench::simulate_study(config, options);
  std::printf(
      "%s: %d simulated participants (observer threshold %s, slope %s, guess %s, lapse %s), %.1f s on %d threads\n",
      config_path.c_str(), options.participants, cell(result.observer_threshold).c_str(),
      cell(result.observer_slope).c_str(), cell(result.observer_guess).c_str(), cell(result.observer_lapse).c_str(),
      result.wall_s, result.threads);
  std::printf("%-12s %-18s %-10s %6s %8s %6s %9s %9s %8s %8s %8s %8s %8s\n", "block", "procedure", "variant", "max_n",
              "truth", "N", "estimates", "mean", "bias", "SD", "RMSE", "|bias|/SD", "trials");
  nlohmann::json rows = nlohmann::json::array();
  for (const bench::ProcedureSummary& s : result.summaries) {
    const double ratio = std::abs(s.bias) / s.sd;
    std::printf("%-12s %-18s %-10s %6s %8s %6d %9d %9s %8s %8s %8s %8s %8s\n", s.block.c_str(), s.procedure.c_str(),
                s.variant.empty() ? "-" : s.variant.c_str(), s.max_trials ? std::to_string(s.max_trials).c_str() : "-",
                cell(s.truth).c_str(), s.participants, s.estimates, cell(s.mean_estimate).c_str(),
                cell(s.bias, 3).c_str(), cell(s.sd, 3).c_str(), cell(s.rmse, 3).c_str(), cell(ratio, 2).c_str(),
                cell(s.mean_trials, 4).c_str());
    rows.push_back({{"block", s.block},
                    {"procedure", s.procedure},
                    {"kind", s.kind},
                    {"variant", s.variant},
                    {"max_trials", s.max_trials},
                    {"truth", s.truth},
                    {"participants", s.participants},
                    {"estimates", s.estimates},
                    {"mean_estimate", s.mean_estimate},
                    {"bias", s.bias},
                    {"sd", s.sd},
                    {"rmse", s.rmse},
                    {"mean_trials", s.mean_trials}});
  }
  std::printf(
      "truth: the level each procedure aims at (constant stimuli and QUEST+: p_see = 1/2; a staircase: its "
      "target p_report); no frames are rendered (the observer answers from the level)\n");
  std::printf(
      "headline per group, as fovlab analyze gives it for these participants' answers, against what its method aims "
      "at:\n");
  nlohmann::json headlines = nlohmann::json::array();
  for (const bench::HeadlineCheck& check : result.headlines) {
    const analysis::Headline& headline = check.headline;
    std::string figure =
        headline.value ? cell(*headline.value) : std::string(analysis::headline_status_name(headline.status));
    if (headline.lower) figure += " " + format_interval(*headline.lower, *headline.upper, 4);
    const bool holds = headline.lower && check.aim >= *headline.lower && check.aim <= *headline.upper;
    std::printf("  %-20s %-24s aims at %-8s %s  (%s)%s\n", headline.group.label().c_str(), figure.c_str(),
                cell(check.aim).c_str(),
                std::isnan(check.aim) ? "-"
                : holds               ? "inside the interval"
                                      : "OUTSIDE the interval",
                headline.method.c_str(), headline.reason.empty() ? "" : ("; " + headline.reason).c_str());
    headlines.push_back({{"group", headline.group.label()},
                         {"status", analysis::headline_status_name(headline.status)},
                         {"reason", headline.reason},
                         {"method", headline.method},
                         {"aims_at", headline.aims_at},
                         {"value", headline.value ? nlohmann::json(*headline.value) : nlohmann::json()},
                         {"lower", headline.lower ? nlohmann::json(*headline.lower) : nlohmann::json()},
                         {"upper", headline.upper ? nlohmann::json(*headline.upper) : nlohmann::json()},
                         {"aim", std::isnan(check.aim) ? nlohmann::json() : nlohmann::json(check.aim)}});
  }
  if (!json_path.empty()) {
    nlohmann::json report = {{"config", config_path},
                             {"participants", options.participants},
                             {"observer",
                              {{"threshold", result.observer_threshold},
                               {"slope", result.observer_slope},
                               {"guess", result.observer_guess},
                               {"lapse", result.observer_lapse}}},
                             {"wall_s", result.wall_s},
                             {"threads", result.threads},
                             {"summaries", rows},
                             {"headlines", headlines}};
    write_text_atomically(json_path, report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  }
}

// QUEST+'s choice (the expected entropy of every level) at `levels` levels and a parameter grid
// of `thresholds` x `slopes` x `lapses`, after `answers` simulated answers; the median of `repeats`.
void bench_quest(int levels, int thresholds, int slopes, int lapses, int repeats) {
  if (levels < 2 || size_t(levels) > kQuestPlusMaxLevels)
    throw InputError("--levels: expected 2 to " + std::to_string(kQuestPlusMaxLevels) + ", got " +
                     std::to_string(levels));
  if (thresholds < 1 || slopes < 1 || lapses < 1 ||
      size_t(thresholds) * size_t(slopes) * size_t(lapses) > kQuestPlusMaxParameters)
    throw InputError("--thresholds/--slopes/--lapses: expected 1 or more each and at most " +
                     std::to_string(kQuestPlusMaxParameters) + " grid points in all");
  if (repeats < 1 || repeats > 10000) throw InputError("--repeats: expected 1 to 10000");
  std::vector<double> grid;
  for (int i = 0; i < levels; ++i) grid.push_back(1.0 + i);
  QuestPlusRule rule;
  rule.guess = 0.05;
  rule.max_trials = 1000;
  for (int i = 0; i < thresholds; ++i)
    rule.thresholds.push_back(1.0 + (levels - 1.0) * i / std::max(1, thresholds - 1));
  rule.slopes = {};
  for (int i = 0; i < slopes; ++i) rule.slopes.push_back(0.1 * std::pow(1.25, i));
  for (int i = 0; i < lapses; ++i) rule.lapses.push_back(0.01 * i);
  if (const std::optional<std::string> error = quest_plus_rule_error(rule, grid))
    throw InputError("bench-quest: " + *error);
  const auto table_start = std::chrono::steady_clock::now();
  const QuestPlus quest(rule, grid);
  const double table_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - table_start).count();
  QuestPlusState state = quest.start();
  for (int i = 0; i < 10; ++i) state = quest.next(state, i % 3 != 0);  // a posterior that is not flat
  std::vector<double> seconds;
  int chosen = 0;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    chosen += quest.choose(state.posterior);
    seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(seconds.begin(), seconds.end());
  std::printf("QUEST+ choice: %d levels x %zu parameter grid points (%d thresholds x %d slopes x %d lapses)\n", levels,
              quest.parameter_count(), thresholds, slopes, lapses);
  std::printf(
      "median %.3f ms, min %.3f ms, max %.3f ms over %d choices (table of p_report: %.1f ms once); "
      "one refresh at 60 Hz is 16.7 ms, at 90 Hz 11.1 ms (checksum %d)\n",
      1e3 * seconds[seconds.size() / 2], 1e3 * seconds.front(), 1e3 * seconds.back(), repeats, 1e3 * table_s, chosen);
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto config_path = std::make_shared<std::string>();
  auto options = std::make_shared<bench::SimulationOptions>();
  auto json_path = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "simulate", "Simulated participants through a study's procedures: bias, spread and trials of each threshold");
  command->add_option("config", *config_path, "Study config (TOML)")->required();
  command->add_option("--participants", options->participants, "Simulated participants (default 100)");
  command->add_option("--observer", options->observer,
                      "Observer model, as fovlab run --observer, without seed= (default \"simulated\")");
  command
      ->add_option("--max-trials", options->max_trials,
                   "Each adaptive procedure's max_trials, comma-separated: one simulation per value")
      ->delimiter(',');
  command->add_option("--threads", options->threads, "Threads (default: every core)");
  add_output_option(*command, "--json", *json_path, "Also write the table as JSON",
                    {{OutputKind::file}, kReplacesAFile});
  command->callback([config_path, options, json_path] { simulate(*config_path, *options, *json_path); });

  auto levels = std::make_shared<int>(int(kQuestPlusMaxLevels));
  auto thresholds = std::make_shared<int>(200);
  auto slopes = std::make_shared<int>(20);
  auto lapses = std::make_shared<int>(5);
  auto repeats = std::make_shared<int>(50);
  CLI::App* quest =
      app.add_subcommand("bench-quest", "Time QUEST+'s choice of the next level (default: the largest grid allowed)");
  quest->add_option("--levels", *levels, "Levels to choose from (default 100, the most allowed)");
  quest->add_option("--thresholds", *thresholds, "Threshold grid points (default 200)");
  quest->add_option("--slopes", *slopes, "Slope grid points (default 20)");
  quest->add_option("--lapses", *lapses, "Lapse grid points (default 5; 200 x 20 x 5 = 20000, the most allowed)");
  quest->add_option("--repeats", *repeats, "Choices timed (default 50)");
  quest->callback([=] { bench_quest(*levels, *thresholds, *slopes, *lapses, *repeats); });
}

}  // namespace fovlab::app
