// Ye et al. 2022's two analysis outputs (docs/analysis.md, "Ye et al. 2022: pilot grid and preference table"):
// the pilot's mean score per pair of two grid parameters with the best pair (4.4.1, Figure 9), on
// hand-made rating studies and one fabricated session log; the grid skipped when the variants form
// none; and Table 2's rows (votes for the reference, one-sided exact binomial, stars, Clopper-Pearson)
// from the paper's counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "analysis/report/report.h"
#include "analysis/study/preference_table.h"
#include "analysis/study/rating_grid.h"
#include "analysis/study/study_analysis.h"
#include "study/config/study_config.h"
#include "study/log/event_log.h"
#include "study/schedule/study_plan.h"
#include "tests/support/temp_dir.h"

namespace fovlab::analysis {
namespace {

namespace fs = std::filesystem;

const std::vector<double> kX = {0.05, 0.3, 0.55};  // focal_share_x
const std::vector<double> kY = {0.3, 0.8};         // focal_share_y
const std::vector<double> kSigma = {2.2, 2.8};

std::string variant_name(size_t column, size_t row) {
  return "x" + std::to_string(column) + "_y" + std::to_string(row);
}

// Variants setting focal_share_x and focal_share_y on the 3 x 2 grid, listed y-major on purpose
// (the grid must not depend on the config's order).
std::vector<VariantConfig> grid_variants() {
  std::vector<VariantConfig> variants;
  for (size_t column = 0; column < kX.size(); ++column)
    for (size_t row = 0; row < kY.size(); ++row)
      variants.push_back({variant_name(column, row), {{"focal_share_x", kX[column]}, {"focal_share_y", kY[row]}}});
  return variants;
}

StudyData pilot_study(std::vector<VariantConfig> variants = grid_variants()) {
  StudyData data;
  data.study = "pilot";
  data.protocol = ProtocolKind::rating;
  data.level_parameter = "sigma";
  data.levels = kSigma;
  data.higher_is_better = false;
  data.reference_method = RenderMethod::ground_truth;
  data.test_method = sampled_method(0, SamplingModel::rectangular);
  data.variants = std::move(variants);
  return data;
}

StudyTrial rating_trial(const std::string& scene, size_t column, size_t row, double level, const std::string& answer) {
  StudyTrial trial;
  trial.scene = scene;
  trial.variant = variant_name(column, row);
  trial.level = level;
  trial.condition = trial.variant + "/level=" + std::to_string(level);
  trial.method = "rmfr";
  trial.answers = {answer};
  trial.answer_steps = {0};
  return trial;
}

using Score = std::function<int(int participant, const std::string& scene, size_t column, size_t row, size_t level)>;

// Two participants x two scenes x every cell x every level, one rating each by `score`.
void add_balanced_trials(StudyData& data, const Score& score) {
  for (int p = 0; p < 2; ++p) {
    ParticipantData participant;
    participant.participant = "P00" + std::to_string(p + 1);
    for (const std::string scene : {"a", "b"})
      for (size_t column = 0; column < kX.size(); ++column)
        for (size_t row = 0; row < kY.size(); ++row)
          for (size_t level = 0; level < kSigma.size(); ++level)
            participant.trials.push_back(
                rating_trial(scene, column, row, kSigma[level], std::to_string(score(p, scene, column, row, level))));
    data.participants.push_back(participant);
  }
}

// Scene a: (0.3, 0.8) always 3; scene b: (0.05, 0.3) always 3; everything else 1 or 2.
int pilot_score(int participant, const std::string& scene, size_t column, size_t row, size_t level) {
  if (scene == "a" && column == 1 && row == 1) return 3;
  if (scene == "b" && column == 0 && row == 0) return 3;
  return 1 + int((column + 2 * row + size_t(participant) + level + (scene == "b" ? 1 : 0)) % 2);
}

const GridMap& map_of(const RatingGrid& grid, const std::string& scene, std::optional<double> level = std::nullopt) {
  for (const GridMap& map : grid.maps)
    if (map.scene == scene && map.level == level) return map;
  throw std::runtime_error("no map for " + scene);
}

AnalysisOptions quick_options() {
  AnalysisOptions options;
  options.bootstrap_samples = 0;
  options.shapes = {};
  return options;
}

TEST(RatingGrid, FindsTheTwoParametersOfTheVariants) {
  const std::optional<ParameterGrid> grid =
      find_parameter_grid(sampled_method(0, SamplingModel::rectangular), "sigma", grid_variants());
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->x_key, "focal_share_x");
  EXPECT_EQ(grid->y_key, "focal_share_y");
  EXPECT_EQ(grid->x_values, kX);
  EXPECT_EQ(grid->y_values, kY);
  // Variants are listed x-major: (x0,y0), (x0,y1), (x1,y0), ...; cells are row-major (y rows).
  EXPECT_EQ(grid->cell_of_variant, (std::vector<size_t>{0, 3, 1, 4, 2, 5}));
}

TEST(RatingGrid, MeansOverLevelsAndParticipantsAndTheBestPair) {
  StudyData data = pilot_study();
  add_balanced_trials(data, pilot_score);
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_TRUE(result.rating_grid);
  const RatingGrid& grid = *result.rating_grid;
  // a, b, all; each over every level and at each of the two levels.
  ASSERT_EQ(grid.maps.size(), 9u);
  EXPECT_EQ(grid.maps[0].scene, "a");
  EXPECT_FALSE(grid.maps[0].level);
  EXPECT_EQ(grid.maps[1].level, 2.2);
  EXPECT_EQ(grid.maps[2].level, 2.8);
  EXPECT_EQ(grid.maps[6].scene, "all");

  // Every cell against the definition, computed here the plain way (balanced: every participant has
  // one trial per level, so the mean of participants' means is the mean of every score).
  for (const GridMap& map : grid.maps) {
    ASSERT_EQ(map.cells.size(), 6u);
    for (size_t row = 0; row < kY.size(); ++row)
      for (size_t column = 0; column < kX.size(); ++column) {
        double sum = 0.0;
        int count = 0;
        for (int p = 0; p < 2; ++p)
          for (const std::string scene : {"a", "b"})
            for (size_t level = 0; level < kSigma.size(); ++level) {
              if (map.scene != "all" && map.scene != scene) continue;
              if (map.level && *map.level != kSigma[level]) continue;
              sum += pilot_score(p, scene, column, row, level);
              ++count;
            }
        const GridCell& cell = map.cells[row * kX.size() + column];
        EXPECT_DOUBLE_EQ(cell.x, kX[column]);
        EXPECT_DOUBLE_EQ(cell.y, kY[row]);
        ASSERT_TRUE(cell.mean_score);
        EXPECT_NEAR(*cell.mean_score, sum / count, 1e-12) << map.scene << " " << column << "," << row;
        EXPECT_EQ(cell.trials, uint64_t(count));
        EXPECT_EQ(cell.participants, 2);
      }
  }
  // The best pairs, by hand: a (0.3, 0.8), b (0.05, 0.3), each with 3 throughout.
  const GridMap& a = map_of(grid, "a");
  ASSERT_EQ(a.best.size(), 1u);
  EXPECT_DOUBLE_EQ(a.cells[a.best[0]].x, 0.3);
  EXPECT_DOUBLE_EQ(a.cells[a.best[0]].y, 0.8);
  EXPECT_DOUBLE_EQ(*a.cells[a.best[0]].mean_score, 3.0);
  const GridMap& b = map_of(grid, "b", 2.8);
  ASSERT_EQ(b.best.size(), 1u);
  EXPECT_DOUBLE_EQ(b.cells[b.best[0]].x, 0.05);
  EXPECT_DOUBLE_EQ(b.cells[b.best[0]].y, 0.3);
  // Pooled over a and b the two 3s each meet a 1-or-2 cell of the other scene: a tie at 2.25 or
  // one winner, whatever the pattern gives; the best cells hold the highest mean either way.
  const GridMap& all = map_of(grid, "all");
  ASSERT_FALSE(all.best.empty());
  for (const GridCell& cell : all.cells) EXPECT_LE(*cell.mean_score, *all.cells[all.best[0]].mean_score + 1e-12);
}

TEST(RatingGrid, EachParticipantCountsOnceAndOnlyRatingsOfIncludedParticipantsCount) {
  StudyData data = pilot_study();
  data.levels = {2.2};
  ParticipantData p1;
  p1.participant = "P001";
  for (int repeat = 0; repeat < 3; ++repeat) p1.trials.push_back(rating_trial("s", 0, 0, 2.2, "3"));
  p1.trials.push_back(rating_trial("s", 1, 1, 2.2, ""));  // a timeout: not counted
  StudyTrial check = rating_trial("s", 1, 1, 2.2, "1");   // an attention check: not counted
  check.attention_check = true;
  check.variant.clear();
  p1.trials.push_back(check);
  ParticipantData p2;
  p2.participant = "P002";
  p2.trials.push_back(rating_trial("s", 0, 0, 2.2, "1"));
  p2.trials.push_back(rating_trial("s", 2, 1, 2.2, "2"));
  ParticipantData p3;  // excluded: nothing of theirs counts
  p3.participant = "P003";
  p3.excluded = true;
  p3.trials.push_back(rating_trial("s", 2, 1, 2.2, "3"));
  p3.trials.push_back(rating_trial("s", 1, 1, 2.2, "3"));
  data.participants = {p1, p2, p3};
  const AnalysisResult result = analyse_study(data, quick_options());
  ASSERT_TRUE(result.rating_grid);
  const GridMap& map = map_of(*result.rating_grid, "s");
  // (0.05, 0.3): P001's mean 3 (three trials) and P002's 1: (3 + 1) / 2 = 2, not 10 / 4 = 2.5.
  EXPECT_DOUBLE_EQ(*map.cells[0].mean_score, 2.0);
  EXPECT_EQ(map.cells[0].trials, 4u);
  EXPECT_EQ(map.cells[0].participants, 2);
  EXPECT_DOUBLE_EQ(*map.cells[5].mean_score, 2.0);  // (0.55, 0.8): P002's 2; P003 excluded
  EXPECT_EQ(map.cells[5].participants, 1);
  EXPECT_FALSE(map.cells[4].mean_score);  // (0.3, 0.8): only a timeout, a check and P003
  EXPECT_EQ(map.cells[4].trials, 0u);
  // One scene: no "all"; the map over every level and the one at 2.2.
  EXPECT_EQ(result.rating_grid->maps.size(), 2u);
  // A tie: both cells at 2.
  EXPECT_EQ(map.best, (std::vector<size_t>{0, 5}));
}

TEST(RatingGrid, SkippedWhenTheVariantsFormNoGrid) {
  const auto grid_of = [](const std::vector<VariantConfig>& variants,
                          RenderMethod method = sampled_method(0, SamplingModel::rectangular),
                          const std::string& level_parameter = "sigma") {
    return find_parameter_grid(method, level_parameter, variants);
  };
  std::vector<VariantConfig> full = grid_variants();
  ASSERT_TRUE(grid_of(full));
  EXPECT_FALSE(grid_of({}));
  // A pair missing (5 of 6 cells).
  EXPECT_FALSE(grid_of({full.begin(), full.end() - 1}));
  // A pair set twice, so another is missing.
  std::vector<VariantConfig> twice = full;
  twice.back().parameters = twice.front().parameters;
  EXPECT_FALSE(grid_of(twice));
  // One parameter only varies.
  std::vector<VariantConfig> one_axis = full;
  for (VariantConfig& variant : one_axis) variant.parameters["focal_share_y"] = 0.3;
  EXPECT_FALSE(grid_of(one_axis));
  // Three parameters vary.
  std::vector<VariantConfig> three = full;
  for (size_t i = 0; i < three.size(); ++i) three[i].parameters["max_steps"] = 64.0 + double(i);
  EXPECT_FALSE(grid_of(three));
  // A third parameter at one value throughout is fine.
  std::vector<VariantConfig> constant = full;
  for (VariantConfig& variant : constant) variant.parameters["max_steps"] = 64.0;
  EXPECT_TRUE(grid_of(constant));
  // Variants that set different keys.
  std::vector<VariantConfig> uneven = full;
  uneven[2].parameters["max_steps"] = 64.0;
  EXPECT_FALSE(grid_of(uneven));
  // The levels' parameter is one of the two.
  EXPECT_FALSE(grid_of(full, sampled_method(0, SamplingModel::rectangular), "focal_share_y"));
  // A choice parameter is no numeric axis (hyperbolic: equalise off/on x sigma).
  std::vector<VariantConfig> choice;
  for (double equalise : {0.0, 1.0})
    for (double sigma : {2.0, 2.6}) choice.push_back({"v", {{"equalise", equalise}, {"sigma", sigma}}});
  EXPECT_FALSE(grid_of(choice, sampled_method(0, SamplingModel::hyperbolic), ""));
  // A key the test method does not have.
  EXPECT_FALSE(grid_of(full, sampled_method(0, SamplingModel::hyperbolic)));

  // Through the analysis: no grid, and no rating_grid.csv nor heat map in the report.
  StudyData data = pilot_study(one_axis);
  add_balanced_trials(data, pilot_score);
  const AnalysisResult result = analyse_study(data, quick_options());
  EXPECT_FALSE(result.rating_grid);
  // Not a rating study: the same grid is not read.
  StudyData same_different = pilot_study();
  same_different.protocol = ProtocolKind::two_afc;
  EXPECT_FALSE(rating_grid(same_different));
  fovlab::testing::TempDir dir("rating-grid-skip");
  for (const std::string& path : write_analysis_report(result, dir.path().string())) {
    const std::string name = fs::path(path).filename().string();
    EXPECT_NE(name, "rating_grid.csv");
    EXPECT_EQ(name.rfind("rating_grid_", 0), std::string::npos) << name;
  }
}

TEST(RatingGrid, ReportWritesTheCsvAndOneHeatMapPerBlock) {
  StudyData data = pilot_study();
  add_balanced_trials(data, pilot_score);
  const AnalysisResult result = analyse_study(data, quick_options());
  fovlab::testing::TempDir dir("rating-grid-report");
  std::vector<std::string> names;
  for (const std::string& path : write_analysis_report(result, dir.path().string()))
    names.push_back(fs::path(path).filename().string());
  for (const char* name : {"rating_grid.csv", "rating_grid_a.svg", "rating_grid_b.svg", "rating_grid_all.svg"})
    EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << name;
  std::ifstream csv_file(dir.path() / "rating_grid.csv");
  std::string header;
  std::getline(csv_file, header);
  EXPECT_EQ(header, "study,scene,level,x_key,x,y_key,y,mean_score,trials,participants,best");
  int rows = 0, best = 0;
  for (std::string line; std::getline(csv_file, line); ++rows) best += line.ends_with(",true") ? 1 : 0;
  EXPECT_EQ(rows, 9 * 6);  // nine maps of six cells
  EXPECT_GE(best, 9);
  std::ifstream svg_file(dir.path() / "rating_grid_a.svg");
  const std::string svg((std::istreambuf_iterator<char>(svg_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(svg.find(">focal_share_x</text>"), std::string::npos);
  EXPECT_NE(svg.find(">focal_share_y</text>"), std::string::npos);
  EXPECT_NE(svg.find(">3.00</text>"), std::string::npos);                           // the best cell's value
  EXPECT_NE(svg.find("stroke=\"#000000\" stroke-width=\"3\""), std::string::npos);  // its outline
  // The colour bar runs over the score's scale 1..3, whatever the data span.
  EXPECT_NE(svg.find(">1</text>"), std::string::npos);
  EXPECT_NE(svg.find(">3</text>"), std::string::npos);
  // The grid's definition (thresholds.json) and its section of report.html cite the paper by
  // authors and year, never by a seed number (issue 38).
  for (const char* name : {"thresholds.json", "report.html"}) {
    std::ifstream file(dir.path() / name);
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("Ye et al. 2022, 4.4.1"), std::string::npos) << name;
    EXPECT_EQ(text.find("eed 00"), std::string::npos) << name;
  }
}

// A session log as `fovlab run` writes it, small: a rating study whose config (carried in the header)
// has four variants on a 2 x 2 grid of focal shares; one participant, one scene, each variant at two
// levels. The grid must come from the config the log carries.
TEST(RatingGrid, ReadsTheVariantsFromTheConfigTheLogCarries) {
  const std::string config = R"([study]
name = "grid_log"
seed = 7

[display]
width_px = 256
height_px = 144
refresh_hz = 60
diagonal_in = 27
viewing_distance_mm = 500

[stimulus]
duration_s = 1.0
frames_per_second = 1

[stimulus.reference]
method = "gt"

[stimulus.test]
method = "rmfr"

[[stimulus.variant]]
name = "lo_lo"
focal_share_x = 0.1
focal_share_y = 0.2
[[stimulus.variant]]
name = "lo_hi"
focal_share_x = 0.1
focal_share_y = 0.6
[[stimulus.variant]]
name = "hi_lo"
focal_share_x = 0.5
focal_share_y = 0.2
[[stimulus.variant]]
name = "hi_hi"
focal_share_x = 0.5
focal_share_y = 0.6

[levels]
parameter = "sigma"
values = [2.2, 2.8]
higher_is_better = false

[protocol]
kind = "rating"
counterbalance = false

[[block]]
scene = "primitives"
)";
  const fs::path folder = fovlab::testing::fresh_scratch_folder("fovlab-rating-grid-log") / "grid_log" / "P001";
  fs::create_directories(folder);
  const std::string path = (folder / "events.jsonl").string();
  {
    // The header and the trials as the schedule makes them for P001 (each variant at each level once,
    // in the schedule's order): every reader holds a log to the config it carries.
    const StudyConfig parsed = parse_logged_study_config(config, "grid.toml", log_schema_version, nullptr);
    const StudyPlan plan = make_study_plan(parsed, "P001");
    EventLogWriter log(path, "", 0);
    nlohmann::json stimuli = nlohmann::json::array();
    for (const PlannedStimulus& stimulus : plan.stimuli)
      stimuli.push_back({{"is_reference", stimulus.is_reference},
                         {"method", stimulus.is_reference ? "gt" : "rmfr"},
                         {"level", stimulus.level ? nlohmann::json(*stimulus.level) : nlohmann::json()},
                         {"scene", "primitives"},
                         {"variant", stimulus.variant}});
    log.append({{"event", "session_header"},
                {"schema_version", log_schema_version},
                {"study", "grid_log"},
                {"participant", "P001"},
                {"config_hash", parsed.hash},
                {"session_seed", plan.session_seed},
                {"config_toml", config},
                {"protocol", "rating"},
                {"stimuli", stimuli},
                {"observer", "human"},
                {"t", 0.0}});
    log.append({{"event", "block_start"}, {"block", 0}, {"name", "primitives"}, {"scene", "primitives"}, {"t", 0.1}});
    // hi_lo scores 3 at both levels; lo_lo 1 and 2; the others 2.
    const std::vector<std::string> variants = {"lo_lo", "lo_hi", "hi_lo", "hi_hi"};
    const std::vector<std::vector<std::string>> answers = {{"1", "2"}, {"2", "2"}, {"3", "3"}, {"2", "2"}};
    ASSERT_EQ(plan.trials.size(), 8u);
    for (const Trial& trial : plan.trials) {
      const size_t v = size_t(std::find(variants.begin(), variants.end(), trial.variant) - variants.begin());
      ASSERT_LT(v, variants.size());
      const size_t l = trial.level == 2.2 ? 0 : 1;
      const double t = 1.0 + trial.index;
      log.append({{"event", "trial_start"},
                  {"trial", trial.index},
                  {"block", 0},
                  {"condition", trial.condition},
                  {"variant", trial.variant},
                  {"level", *trial.level},
                  {"attention_check", false},
                  {"sequence", trial.sequence},
                  {"reference_first", trial.reference_first},
                  {"t", t}});
      log.append(
          {{"event", "response"}, {"trial", trial.index}, {"step", 0}, {"answer", answers[v][l]}, {"t", t + 0.5}});
      log.append({{"event", "trial_end"}, {"trial", trial.index}, {"t", t + 0.6}});
    }
  }
  const StudyData data = load_study({path});
  ASSERT_EQ(data.participants.size(), 1u) << (data.left_out.empty() ? "" : data.left_out[0].reason);
  EXPECT_EQ(data.test_method, sampled_method(0, SamplingModel::rectangular));
  ASSERT_EQ(data.variants.size(), 4u);
  EXPECT_DOUBLE_EQ(data.variants[2].parameters.at("focal_share_x"), 0.5);
  const std::optional<RatingGrid> grid = rating_grid(data);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->x_values, (std::vector<double>{0.1, 0.5}));
  EXPECT_EQ(grid->y_values, (std::vector<double>{0.2, 0.6}));
  const GridMap& map = map_of(*grid, "primitives");
  // Cells row-major: (0.1, 0.2) lo_lo, (0.5, 0.2) hi_lo, (0.1, 0.6) lo_hi, (0.5, 0.6) hi_hi.
  EXPECT_DOUBLE_EQ(*map.cells[0].mean_score, 1.5);
  EXPECT_DOUBLE_EQ(*map.cells[1].mean_score, 3.0);
  EXPECT_DOUBLE_EQ(*map.cells[2].mean_score, 2.0);
  EXPECT_DOUBLE_EQ(*map.cells[3].mean_score, 2.0);
  EXPECT_EQ(map.best, (std::vector<size_t>{1}));
  EXPECT_DOUBLE_EQ(*map_of(*grid, "primitives", 2.2).cells[0].mean_score, 1.0);
}

// ---- Table 2 ----------------------------------------------------------------------------------

TEST(PreferenceTable, PaperCountsGiveTheStarsOfTable2) {
  // Ye et al. 2022, Table 2: RMFR against hyperbolic, linear, log-polar (KFR) and full resolution, 72 votes
  // each (12 participants x 6 scenes).
  const std::vector<PreferenceCount> counts = {
      {"rmfr_2afc_hyperbolic", {"all", ""}, "test", "rmfr", "hyperbolic", 49, 72},
      {"rmfr_2afc_linear", {"all", ""}, "test", "rmfr", "linear", 47, 72},
      {"rmfr_2afc_kfr", {"all", ""}, "test", "rmfr", "kfr", 50, 72},
      {"rmfr_2afc_gt", {"all", ""}, "test", "rmfr", "gt", 35, 72}};
  const std::vector<PreferenceRow> rows = preference_table(counts);
  ASSERT_EQ(rows.size(), 4u);
  // Shares as printed: 68.1 %, 65.3 %, 69.4 %, 48.6 %.
  const std::vector<double> printed = {68.1, 65.3, 69.4, 48.6};
  // P(X >= k), X ~ Binomial(72, 1/2), exactly (sum of C(72, i) / 2^72 in rational arithmetic).
  const std::vector<double> p_greater = {0.001471380265062488, 0.0063872977690324515, 0.0006467924813381441,
                                         0.6380259271265429};
  const std::vector<std::string> stars = {"**", "**", "***", "n.s."};
  // Clopper-Pearson 95 % (bisection on exact tails): [.560, .786] [.531, .761] [.575, .798] [.367, .607].
  const std::vector<std::pair<double, double>> interval = {{0.5601415634714659, 0.7855820639126871},
                                                           {0.5313671687187012, 0.7611872305946361},
                                                           {0.5746833466855246, 0.7976201305699326},
                                                           {0.3665002788192331, 0.6068999535203381}};
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].study, counts[i].study);
    EXPECT_EQ(rows[i].test_method, counts[i].test_method);
    EXPECT_EQ(rows[i].reference_votes, counts[i].reference_votes);
    EXPECT_EQ(rows[i].n, 72u);
    EXPECT_NEAR(100.0 * rows[i].share, printed[i], 0.05);
    EXPECT_NEAR(rows[i].p_value, p_greater[i], 1e-7 * p_greater[i]);
    EXPECT_EQ(rows[i].stars, stars[i]) << counts[i].reference_votes << "/72";
    EXPECT_NEAR(rows[i].interval.lower, interval[i].first, 1e-9);
    EXPECT_NEAR(rows[i].interval.upper, interval[i].second, 1e-9);
  }
  EXPECT_THROW(preference_table({{"s", {"a", ""}, "test", "rmfr", "gt", 3, 2}}), std::invalid_argument);
  EXPECT_THROW(preference_table({{"s", {"a", ""}, "test", "rmfr", "gt", 0, 0}}), std::invalid_argument);
}

// A 2afc "better" study analysed with the default two-sided alternative: its condition rows say
// 47/72 is "*" (two-sided p 0.0128), the preference table still "**" (one-sided 0.0064), and it
// counts the votes for the reference (n - k, k counting the test).
TEST(PreferenceTable, IsOneSidedWhateverTheAlternativeAndCountsTheReference) {
  StudyData data;
  data.study = "rmfr_2afc_linear";
  data.protocol = ProtocolKind::two_afc;
  data.question = TwoAfcQuestion::better;
  data.reference_method = sampled_method(0, SamplingModel::rectangular);
  data.test_method = sampled_method(0, SamplingModel::linear);
  ParticipantData participant;
  participant.participant = "P001";
  // 72 trials on one scene, 25 won by the test (so 47 by the reference), order alternating.
  for (int i = 0; i < 72; ++i) {
    StudyTrial trial;
    trial.index = i;
    trial.scene = "temple";
    trial.condition = "test";
    trial.method = "linear";
    trial.reference_first = i % 2 == 0;
    const bool test_wins = i < 25;
    const bool test_first = !trial.reference_first;
    trial.answers = {test_wins == test_first ? "first" : "second"};
    participant.trials.push_back(trial);
  }
  data.participants.push_back(participant);
  const AnalysisResult result = analyse_study(data, quick_options());  // two-sided
  ASSERT_EQ(result.conditions.size(), 1u);
  EXPECT_EQ(result.conditions[0].k, 25u);
  ASSERT_EQ(result.preferences.size(), 1u);
  const PreferenceRow& row = result.preferences[0];
  EXPECT_EQ(row.reference_votes, 47u);
  EXPECT_EQ(row.n, 72u);
  EXPECT_EQ(row.reference_method, "rmfr");
  EXPECT_EQ(row.test_method, "linear");
  EXPECT_EQ(row.group.scene, "temple");
  EXPECT_EQ(row.condition, "test");
  EXPECT_NEAR(row.p_value, 0.0063872977690324515, 1e-12);
  EXPECT_EQ(row.stars, "**");
  // The condition row, two-sided, from the test's side: 25/72 gives p 0.0128, "*".
  EXPECT_NEAR(result.conditions[0].p_value, 0.01277, 1e-5);
  EXPECT_EQ(result.conditions[0].stars, "*");

  // The report: preference.csv, one-sided in its column, and a table in report.html.
  fovlab::testing::TempDir dir("preference-report");
  write_analysis_report(result, dir.path().string());
  std::ifstream csv_file(dir.path() / "preference.csv");
  std::string header, line;
  std::getline(csv_file, header);
  std::getline(csv_file, line);
  EXPECT_EQ(header,
            "study,scene,variant,condition,reference_method,test_method,n,reference_votes,share,ci_lower,"
            "ci_upper,p_value,alternative,stars,log10_p");
  EXPECT_EQ(line.rfind("rmfr_2afc_linear,temple,,test,rmfr,linear,72,47,0.6527777778,", 0), 0u) << line;
  EXPECT_NE(line.find(",greater,**,-2.19"), std::string::npos) << line;  // log10 0.0064
  std::ifstream html_file(dir.path() / "report.html");
  const std::string html((std::istreambuf_iterator<char>(html_file)), std::istreambuf_iterator<char>());
  EXPECT_NE(html.find("<h2 id=\"preference\">"), std::string::npos);
  EXPECT_NE(html.find("one-sided (greater"), std::string::npos);
  EXPECT_NE(html.find("<td>rmfr v. linear</td>"), std::string::npos);
  // The table cites its paper by authors and year, never by a seed number (issue 38).
  EXPECT_NE(html.find("Ye et al. 2022, Table 2"), std::string::npos);
  EXPECT_EQ(html.find("eed 00"), std::string::npos);

  // Any other protocol: no table.
  StudyData same = data;
  same.question = TwoAfcQuestion::same;
  for (StudyTrial& trial : same.participants[0].trials) trial.answers = {"same"};
  EXPECT_TRUE(analyse_study(same, quick_options()).preferences.empty());
}

}  // namespace
}  // namespace fovlab::analysis
