// fovlab bench end to end with FIPR: a tiny sweep writes every cell (JSON, Markdown, images, Pareto
// charts) with speed-ups that are the ratio of the medians; the same sweep in parts (--cells I/N)
// merged by bench-merge gives the same report; bad flags exit 2 with one line naming the flag and
// write nothing. Speed is reported, never asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <set>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "tests/app/cli_test_support.h"

namespace {

namespace fs = std::filesystem;

using fovlab::cli_test::CommandResult;
using fovlab::cli_test::expect_one_line_error;
using fovlab::cli_test::read_all;
using fovlab::cli_test::run;

fs::path scratch() { return fovlab::cli_test::scratch("fovlab-bench-cli-test"); }

const std::string kTiny = "bench --scenes primitives --spp 1 --width 64 --height 48 --repeats 1 ";

TEST(BenchCli, FiprSweepWritesEveryCellWithSpeedUpsAndParetoCharts) {
  const fs::path json_path = scratch() / "sweep.json";
  const fs::path out_dir = scratch() / "sweep";
  const CommandResult result = run(kTiny + "--methods gt,ipr,fipr --refresh 1,2 --fovea-deg 5,7.5 --json " +
                                   json_path.string() + " --out-dir " + out_dir.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("| primitives | 0 | 1 | fipr | 2 | 7.5 |"), std::string::npos)
      << result.out;  // scene time 0
  EXPECT_NE(result.out.find("FIPR at a fovea of 7.5 degrees"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("| primitives | 1 | 2 |"), std::string::npos) << result.out;  // the 7.5-degree table

  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  ASSERT_EQ(json["rows"].size(), 1u);  // GT against IPR, as without FIPR
  EXPECT_TRUE(json["rows"][0].contains("flip"));
  EXPECT_NE(json["command"].get<std::string>().find("--methods gt,ipr,fipr --refresh 1,2 --fovea-deg 5,7.5"),
            std::string::npos);
  const nlohmann::json& cells = json["cells"];
  ASSERT_EQ(cells.size(), 6u);  // GT, IPR and 2 refresh x 2 foveae
  double gt_ms = 0.0;
  std::set<std::pair<int, double>> variants;
  for (const nlohmann::json& cell : cells) {
    EXPECT_EQ(cell["scene"], "primitives");
    EXPECT_EQ(cell["spp"], 1);
    ASSERT_TRUE(cell["command"].is_string());
    const std::string method = cell["method"].get<std::string>();
    if (method == "gt") gt_ms = cell["median_gpu_ms"].get<double>();
    const double ssim = cell["ssim"].get<double>();
    EXPECT_GT(ssim, 0.0) << method;
    EXPECT_LE(ssim, 1.0) << method;
    EXPECT_GE(cell["flip"].get<double>(), 0.0) << method;
    EXPECT_LE(cell["flip"].get<double>(), 1.0) << method;
    EXPECT_TRUE(cell.contains("fpsnr_db"));
    EXPECT_TRUE(cell["pareto_flip"].is_boolean());
    EXPECT_TRUE(cell["pareto_one_minus_ssim"].is_boolean());
    if (method != "fipr") continue;
    const int refresh = cell["refresh"].get<int>();
    const double fovea = cell["fovea_deg"].get<double>();
    variants.emplace(refresh, fovea);
    EXPECT_EQ(cell["gpu_ms_runs"].size(), 1u);
    const double ms = cell["median_gpu_ms"].get<double>();
    ASSERT_GT(ms, 0.0);
    EXPECT_DOUBLE_EQ(cell["gt_median_gpu_ms"].get<double>(), gt_ms);
    EXPECT_DOUBLE_EQ(cell["speedup"].get<double>(), gt_ms / ms);
    const double top = cell["top_level_share"].get<double>();
    const double refreshed = cell["refreshed_share"].get<double>();
    EXPECT_GT(top, 0.0);  // the fovea at the centre is traced in full
    EXPECT_LE(top, 1.0);
    EXPECT_GE(refreshed, 0.0);
    EXPECT_NEAR(top + refreshed + cell["kept_share"].get<double>(), 1.0, 1e-9);
    EXPECT_GT(cell["steps_per_pixel"].get<double>(), 0.0);
    // Timed frames continue the sequence after one refresh cycle of warm-up.
    EXPECT_EQ(cell["warmup_frames"], refresh);
    EXPECT_EQ(cell["timed_frame_indices"][0], refresh);
    const std::string command = cell["command"].get<std::string>();
    EXPECT_NE(command.find("--methods gt,fipr --refresh " + std::to_string(refresh) + " --fovea-deg "),
              std::string::npos)
        << command;
    EXPECT_TRUE(fs::exists(out_dir / ("primitives_spp1_fipr_r" + std::to_string(refresh) + "_fovea" +
                                      (fovea == 5.0 ? "5" : "7.5") + "_mask.png")));
  }
  EXPECT_EQ(variants, (std::set<std::pair<int, double>>{{1, 5.0}, {1, 7.5}, {2, 5.0}, {2, 7.5}}));
  // GT is the reference (error 0, speed-up 1): nothing dominates it.
  EXPECT_TRUE(cells[0]["pareto_flip"].get<bool>());

  for (const char* chart : {"primitives_pareto_flip.svg", "primitives_pareto_ssim.svg"}) {
    const std::string svg = read_all(out_dir / chart);
    EXPECT_EQ(svg.rfind("<svg", 0), 0u) << chart;
    EXPECT_NE(svg.find("Pareto front (not dominated)"), std::string::npos) << chart;
    EXPECT_NE(svg.find(">1/2/7.5</text>"), std::string::npos) << chart;  // a FIPR cell's label
    EXPECT_NE(svg.find(">ipr 1</text>"), std::string::npos) << chart;
  }
  // A cell's command reproduces that cell alone (GT and the one FIPR variant).
  const std::string command = cells.back()["command"].get<std::string>();
  ASSERT_EQ(command.rfind("fovlab bench ", 0), 0u) << command;
  const fs::path cell_json = scratch() / "cell.json";
  const CommandResult again = run(command.substr(std::string("fovlab ").size()) + " --json " + cell_json.string());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const nlohmann::json cell = nlohmann::json::parse(read_all(cell_json));
  ASSERT_EQ(cell["cells"].size(), 2u);
  EXPECT_EQ(cell["cells"][1]["refresh"], cells.back()["refresh"]);
  EXPECT_EQ(cell["cells"][1]["fovea_deg"], cells.back()["fovea_deg"]);
  EXPECT_EQ(cell["cells"][1]["foveation"], cells.back()["foveation"]);  // every FIPR setting, and the shares

  const std::string table = read_all(out_dir / "table.md");
  EXPECT_NE(table.find("## FIPR at a fovea of 7.5 degrees"), std::string::npos);
  EXPECT_NE(table.find("## Pareto fronts"), std::string::npos);
  EXPECT_TRUE(fs::exists(out_dir / "bench.json"));
}

// Ye et al. 2022's sampling models over several scene times (Figure 12's rotating patterns): a cell per
// time and model with its sampling figures, the models ranked by mean FPSNR.
TEST(BenchCli, SamplingModelsOverSceneTimesAreRankedByFpsnr) {
  const fs::path json_path = scratch() / "models.json";
  const CommandResult result =
      run("bench --scenes rotating-rod --spp 1 --width 64 --height 36 --repeats 1 --times 0,9 "
          "--methods gt,rmfr,kfr --json " +
          json_path.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("Sampling models ranked by mean FPSNR over the scene times"), std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("| rotating-rod | 1 | 1 |"), std::string::npos) << result.out;  // rank 1
  const nlohmann::json json = nlohmann::json::parse(read_all(json_path));
  EXPECT_EQ(json["times_s"], nlohmann::json::array({0.0, 9.0}));
  ASSERT_EQ(json["cells"].size(), 6u);  // 2 times x (gt, rmfr, kfr)
  std::set<std::pair<double, std::string>> seen;
  for (const nlohmann::json& cell : json["cells"]) {
    seen.emplace(cell["time_s"].get<double>(), cell["method"].get<std::string>());
    if (cell["method"] == "gt") continue;
    const nlohmann::json& sampling = cell["sampling"];
    EXPECT_NEAR(sampling["theoretical_speedup"].get<double>(), 64.0 * 36 / (25.0 * 14),
                1e-9);  // round(64/2.6) x round(36/2.6)
    EXPECT_GT(sampling["shaded_samples"].get<double>(), 0.0);
    // The reference is RMFR's buffer at the run's sigma, in the run or not; RMFR's own ratio is 1.
    EXPECT_EQ(sampling["reference"], "rmfr sigma 2.6");
    EXPECT_EQ(sampling["reference_shaded_samples"], 25 * 14);
    EXPECT_DOUBLE_EQ(sampling["shaded_over_reference"].get<double>(),
                     sampling["shaded_samples"].get<double>() / (25.0 * 14));
    if (cell["method"] == "rmfr") {
      EXPECT_EQ(sampling["shaded_over_reference"].get<double>(), 1.0);
    }
    EXPECT_NE(cell["command"].get<std::string>().find("--methods gt," + cell["method"].get<std::string>()),
              std::string::npos);
    EXPECT_NE(cell["command"].get<std::string>().find("--time " + std::to_string(int(cell["time_s"].get<double>()))),
              std::string::npos);
  }
  EXPECT_EQ(seen.size(), 6u);
  EXPECT_NE(result.out.find("| samples / rmfr's |"), std::string::npos) << result.out;
  EXPECT_NE(json["command"].get<std::string>().find("--times 0,9"), std::string::npos);

  // The sweep's command runs as written (it holds only the flags its models use: bench refuses the
  // others) and measures the same cells; bench-merge plans each part's cells from it.
  const std::string command = json["command"].get<std::string>();
  EXPECT_EQ(command.find("--inner-radius-deg"), std::string::npos) << command;  // hyperbolic's and linear's
  const fs::path again_path = scratch() / "models-again.json";
  const CommandResult again = run(command.substr(std::string("fovlab ").size()) + " --json " + again_path.string());
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const nlohmann::json again_json = nlohmann::json::parse(read_all(again_path));
  EXPECT_EQ(again_json["command"], json["command"]);
  ASSERT_EQ(again_json["cells"].size(), json["cells"].size());
  for (size_t i = 0; i < json["cells"].size(); ++i)
    for (const char* key : {"method", "time_s", "spp", "scene"})
      EXPECT_EQ(again_json["cells"][i][key], json["cells"][i][key]) << i;
}

// Figure 6: RMFR over a grid of focal shares, a cell a pair, heat maps and the best pair.
TEST(BenchCli, RmfrFocalSweepWritesHeatMapsAndTheBestPair) {
  const fs::path out_dir = scratch() / "focal";
  fs::remove_all(out_dir);
  const CommandResult result = run(kTiny + "--methods gt,rmfr --fx 0.05,0.55 --fy 0.3 --out-dir " + out_dir.string());
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("RMFR's best f_x, f_y"), std::string::npos) << result.out;
  const nlohmann::json json = nlohmann::json::parse(read_all(out_dir / "bench.json"));
  std::set<std::pair<double, double>> pairs;
  for (const nlohmann::json& cell : json["cells"])
    if (cell["method"] == "rmfr") {
      pairs.emplace(cell["focal_share_x"].get<double>(), cell["focal_share_y"].get<double>());
      EXPECT_NE(cell["command"].get<std::string>().find("--fx " +
                                                        std::string(cell["focal_share_x"] == 0.05 ? "0.05" : "0.55")),
                std::string::npos);
    }
  EXPECT_EQ(pairs, (std::set<std::pair<double, double>>{{0.05, 0.3}, {0.55, 0.3}}));
  EXPECT_NE(json["command"].get<std::string>().find("--fx 0.05,0.55 --fy 0.3"), std::string::npos);
  for (const char* metric : {"fpsnr", "psnr", "ssim"})
    EXPECT_TRUE(fs::exists(out_dir / (std::string("primitives_t0_spp1_rmfr_") + metric + ".svg"))) << metric;
}

// Whether `key` holds a time or something made of times (speed-ups, Pareto marks): what two runs of
// the same sweep may differ in (the marks are checked byte for byte on a cut of one run below).
bool timed(const std::string& key) {
  for (const char* part : {"ms", "speedup", "over_floor", "pareto"})
    if (key.find(part) != std::string::npos) return true;
  return false;
}

// `a` and `b` equal but for timed keys; the first difference's path in `where`.
bool equal_but_times(const nlohmann::json& a, const nlohmann::json& b, std::string& where,
                     const std::string& path = "") {
  if (a.is_object() && b.is_object()) {
    for (const auto& [key, value] : a.items()) {
      if (timed(key)) continue;
      if (!b.contains(key) || !equal_but_times(value, b[key], where, path + "." + key)) {
        if (where.empty()) where = path + "." + key;
        return false;
      }
    }
    for (const auto& [key, value] : b.items())
      if (!a.contains(key)) return where = path + "." + key, false;
    return true;
  }
  if (a.is_array() && b.is_array()) {
    if (a.size() != b.size()) return where = path + " (length)", false;
    for (size_t i = 0; i < a.size(); ++i)
      if (!equal_but_times(a[i], b[i], where, path + "[" + std::to_string(i) + "]")) return false;
    return true;
  }
  if (a != b) where = path;
  return a == b;
}

// A sweep in three parts (one of them empty: 2 units) merged by bench-merge is the report of one run
// of the whole sweep: the same JSON but for times, the same tables and charts; a part missing is one
// line naming it, and nothing is written.
TEST(BenchCli, CellsInPartsMergeIntoTheWholeSweepsReport) {
  const fs::path dir = scratch() / "parts";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // A scene time of more digits than 6: each part's command must give it back exactly for the merge
  // to rebuild the part's cells.
  const std::string sweep =
      "bench --scenes primitives --spp 1,4 --width 64 --height 48 --repeats 1 --methods gt,ipr,fipr "
      "--refresh 1 --fovea-deg 7.5 --time 0.123456789";
  const CommandResult whole =
      run(sweep + " --json " + (dir / "whole.json").string() + " --out-dir " + (dir / "whole").string());
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  std::string parts;
  for (int index = 0; index < 3; ++index) {
    const fs::path part = dir / ("part-" + std::to_string(index) + ".json");
    const CommandResult result = run(sweep + " --cells " + std::to_string(index) + "/3 --json " + part.string());
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find("part " + std::to_string(index) + "/3: " + (index < 2 ? "1" : "0") +
                              " of 2 (scene, time, spp) units"),
              std::string::npos)
        << result.out;
    parts = " " + part.string() + parts;  // given in reverse order
  }
  const CommandResult merged = run("bench-merge" + parts + " --json " + (dir / "merged.json").string() + " --out-dir " +
                                   (dir / "merged").string());
  ASSERT_EQ(merged.exit_code, 0) << merged.err;
  EXPECT_NE(merged.out.find("fovlab bench-merge: 3 parts, 2 (scene, time, spp) units, 6 cells"), std::string::npos)
      << merged.out;
  EXPECT_NE(merged.out.find("FIPR at a fovea of 7.5 degrees"), std::string::npos) << merged.out;
  const nlohmann::json one = nlohmann::json::parse(read_all(dir / "whole.json"));
  const nlohmann::json joined = nlohmann::json::parse(read_all(dir / "merged.json"));
  std::string where;
  EXPECT_TRUE(equal_but_times(one, joined, where)) << "first difference at " << where;
  EXPECT_EQ(joined["cells"].size(), 6u);
  for (const char* file : {"bench.json", "table.md", "primitives_pareto_flip.svg", "primitives_pareto_ssim.svg"})
    EXPECT_TRUE(fs::is_regular_file(dir / "merged" / file)) << file;
  EXPECT_EQ(read_all(dir / "merged" / "bench.json"), read_all(dir / "merged.json"));

  // The whole run's own report cut into two parts (its times, so nothing differs but the cut):
  // merged, the JSON, tables and charts are the whole run's byte for byte, Pareto marks included.
  const nlohmann::json cells_per_unit = one["cells"].size() / one["rows"].size();
  std::string cut_parts;
  for (int index = 0; index < 2; ++index) {
    nlohmann::json part = one;
    part["rows"] = nlohmann::json::array();
    part["cells"] = nlohmann::json::array();
    for (size_t unit = size_t(index); unit < one["rows"].size(); unit += 2) {
      part["rows"].push_back(one["rows"][unit]);
      for (size_t cell = unit * cells_per_unit.get<size_t>(); cell < (unit + 1) * cells_per_unit.get<size_t>();
           ++cell) {
        nlohmann::json value = one["cells"][cell];
        value.erase("pareto_flip");  // made again by the merge
        value.erase("pareto_one_minus_ssim");
        part["cells"].push_back(value);
      }
    }
    part["part"] = {{"index", index}, {"count", 2}, {"units", one["rows"].size()}};
    const fs::path path = dir / ("cut-" + std::to_string(index) + ".json");
    fovlab::cli_test::write_file(path, part.dump(2));
    cut_parts += " " + path.string();
  }
  const CommandResult cut = run("bench-merge" + cut_parts + " --out-dir " + (dir / "cut").string());
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  for (const char* file : {"bench.json", "table.md", "primitives_pareto_flip.svg", "primitives_pareto_ssim.svg"})
    EXPECT_TRUE(read_all(dir / "cut" / file) == read_all(dir / "whole" / file)) << file << " differs from one run's";

  // A part missing: one line naming it, nothing written.
  const CommandResult missing = run("bench-merge " + (dir / "part-0.json").string() + " " +
                                    (dir / "part-2.json").string() + " --json " + (dir / "never.json").string());
  expect_one_line_error(missing, "part 1/3 missing");
  EXPECT_FALSE(fs::exists(dir / "never.json"));
  expect_one_line_error(run("bench-merge " + (dir / "whole.json").string()), "not a part of a sweep");

  // Each part against the sweep its command plans: a part relabelled (part 0 holds unit 0, 1 spp, and
  // part 1 unit 1, 4 spp: their indices swapped), a method no flag planned, a negative time, and a
  // command that is not a sweep's. One line naming the file and the field, nothing written.
  const auto edited = [&](const std::string& name, const std::function<void(nlohmann::json&)>& edit, int index) {
    nlohmann::json part = nlohmann::json::parse(read_all(dir / ("part-" + std::to_string(index) + ".json")));
    edit(part);
    return fovlab::cli_test::write_file(dir / (name + "-" + std::to_string(index) + ".json"), part.dump(2)).string();
  };
  const std::string part_2 = (dir / "part-2.json").string();
  const auto merge = [&](const std::string& a, const std::string& b, const std::string& c) {
    return run("bench-merge " + a + " " + b + " " + c + " --json " + (dir / "never.json").string());
  };
  const std::string relabelled_0 = edited(
      "relabelled", [](nlohmann::json& p) { p["part"]["index"] = 1; }, 0);
  const std::string relabelled_1 = edited(
      "relabelled", [](nlohmann::json& p) { p["part"]["index"] = 0; }, 1);
  expect_one_line_error(merge(relabelled_0, relabelled_1, part_2),
                        "relabelled-1.json: rows[0].spp is 4; expected 1 (unit 0 of the sweep");
  const std::string part_1 = (dir / "part-1.json").string();
  expect_one_line_error(
      merge(edited(
                "xyz", [](nlohmann::json& p) { p["cells"][1]["method"] = "xyz"; }, 0),
            part_1, part_2),
      "xyz-0.json: cells[1].method is \"xyz\"; expected \"ipr\" (cell 2 of every unit's 3: gt, ipr, fipr");
  expect_one_line_error(merge(edited(
                                  "slow", [](nlohmann::json& p) { p["cells"][2]["median_gpu_ms"] = -1.5; }, 0),
                              part_1, part_2),
                        "slow-0.json: cells[2].median_gpu_ms is -1.5; expected a GPU time in milliseconds from 0 to");
  const auto other_command = [](nlohmann::json& p) { p["command"] = "rm -rf /"; };
  expect_one_line_error(
      merge(edited("other", other_command, 0), edited("other", other_command, 1), edited("other", other_command, 2)),
      "other-0.json: \"command\": expected \"fovlab bench\" and the sweep's flags, got \"rm -rf /\"");
  const auto more_spps = [](nlohmann::json& p) {
    std::string command = p["command"];
    command.replace(command.find("--spp 1,4"), 9, "--spp 1,4,16");
    p["command"] = command;
  };
  expect_one_line_error(merge(edited("spp", more_spps, 0), edited("spp", more_spps, 1), edited("spp", more_spps, 2)),
                        "spp-0.json: \"part\".units is 2; expected 3, the sweep's 1 scenes x 1 times x 3 spp");
  EXPECT_FALSE(fs::exists(dir / "never.json"));
  expect_one_line_error(run("bench-merge " + (dir / "nothing.json").string()), "nothing.json");
  // --cells needs --json, and leaves --out-dir to bench-merge.
  expect_one_line_error(run(kTiny + "--cells 0/2"), "--cells 0/2: needs --json");
  expect_one_line_error(
      run(kTiny + "--cells 0/2 --json " + (dir / "x.json").string() + " --out-dir " + (dir / "x").string()),
      "--out-dir");
  expect_one_line_error(run(kTiny + "--cells 2/2 --json " + (dir / "x.json").string()), "--cells");
  EXPECT_FALSE(fs::exists(dir / "x.json"));
}

TEST(BenchCli, BadFlagsExitTwoWithOneLineNamingTheFlagAndWriteNothing) {
  const fs::path json_path = scratch() / "never.json";
  const fs::path out_dir = scratch() / "never";
  const std::string outputs = " --json " + json_path.string() + " --out-dir " + out_dir.string();
  const std::string fipr = kTiny + "--methods gt,fipr ";
  // Each run starts the process (most of a second in a Debug build): one case per kind of mistake.
  const std::pair<std::string, std::string> cases[] = {
      {kTiny + "--methods gt,rtx", "--methods"},
      {kTiny + "--methods ipr,fipr", "--methods"},  // GT is the reference
      {fipr + "--refresh 3", "--refresh"},
      {fipr + "--refresh 1,1", "--refresh"},
      {fipr + "--fovea-deg abc", "--fovea-deg"},
      {fipr + "--fovea-deg 5,200", "--fovea-deg"},
      {kTiny + "--methods gt,ipr --refresh 2", "--refresh"},  // a FIPR flag without fipr
      {fipr + "--levels 2", "--levels 2"},
      {fipr + "--gaze none", "--gaze"},
      {fipr + "--combine sum", "--combine"},
      {"bench --scenes primitives --spp 1 --width 8 --height 48 --repeats 1", "--width 8"},
      {kTiny + "--methods gt,ipr --sigma 2", "--sigma"},  // a sampling flag without a sampling model
      {kTiny + "--methods gt,rmfr --fx 0", "--fx"},
      {kTiny + "--methods gt,rmfr --fy 0.3,0.3", "--fy"},
      {kTiny + "--methods gt,kfr --fx 0.2", "--fx"},  // RMFR's flag, no RMFR
      {kTiny + "--methods gt,rmfr --equalise", "--equalise"},
      {kTiny + "--methods gt,kfr --equalise bogus", "--equalise"},
      {kTiny + "--methods gt,kfr --equalise --sigma 1", "equalise"},  // KFR shades less than the screen
      {kTiny + "--methods gt,linear --equalise --sigma 8", "equalise"},  // 1/64 below the fovea's own density
      {kTiny + "--methods gt,linear --inner-radius-deg 0 --min-probability 0", "--min-probability"},  // nothing shaded
      {kTiny + "--methods gt --time 1 --times 0,1", "--times"},
      {kTiny + "--methods gt --times 0,0", "--times"},
  };
  for (const auto& [arguments, flag] : cases) {
    SCOPED_TRACE(arguments);
    expect_one_line_error(run(arguments + outputs), flag);
    EXPECT_FALSE(fs::exists(json_path));
    EXPECT_FALSE(fs::exists(out_dir));
  }
}

}  // namespace
