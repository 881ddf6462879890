// A sweep in parts (bench/bench_parts.h): part I of N holds units I, I + N, ...; merging the parts
// gives back the whole sweep's rows and cells in order, whatever order the parts come in, and refuses
// a missing part, a part given twice, parts of another sweep, and a part whose rows or cells are not
// its units'.
#include "bench/bench_parts.h"

#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "core/input_error.h"

namespace fovlab::bench {
namespace {

// A sweep's layout: `scenes` scenes "s0", "s1", ... at scene time 0, each at `spps`, two cells a
// unit (gt and ipr), as its command would plan it.
SweepLayout layout_of(int scenes, std::vector<int> spps = {1}) {
  SweepLayout layout;
  for (int scene = 0; scene < scenes; ++scene) layout.scenes.push_back("s" + std::to_string(scene));
  layout.times_s = {0.0f};
  layout.spps = std::move(spps);
  layout.unit_cells = {{BenchMethod::gt}, {BenchMethod::ipr}};
  layout.width = 64;
  layout.height = 36;
  layout.repeats = 1;
  return layout;
}

// The report one run of `layout`'s sweep would write, with the unit's number in each row and cell.
nlohmann::json whole_sweep(const SweepLayout& layout) {
  nlohmann::json report = {{"device", "test device"},
                           {"width", 64},
                           {"height", 36},
                           {"repeats", 1},
                           {"times_s", {0.0}},
                           {"command", "fovlab bench ..."},
                           {"metrics", {{"flip_pixels_per_degree", 1.3}}}};
  const nlohmann::json runs = {{"median_gpu_ms", 2.0},
                               {"steps_per_pixel", 9.5},
                               {"capped_rays", 0},
                               {"median_pass_gpu_ms", {{"trace_level0", 2.0}}}};
  for (const PlannedCell& planned : layout.unit_cells)
    if (planned.method == BenchMethod::fipr)
      report["fipr"] = {{"refresh", {*planned.refresh}}, {"fovea_deg", {*planned.fovea_deg}}};
  if (!layout.focal_shares_x.empty())
    report["sampling_focal_shares"] = {{"x", layout.focal_shares_x}, {"y", layout.focal_shares_y}};
  report["rows"] = nlohmann::json::array();
  report["cells"] = nlohmann::json::array();
  for (int unit = 0; unit < layout.units(); ++unit) {
    const nlohmann::json key = {{"scene", layout.scene_of(unit)}, {"spp", layout.spp_of(unit)}, {"time_s", 0.0}};
    nlohmann::json row = key;
    row["unit"] = unit;
    row["gt"] = runs;
    row["ipr"] = runs;
    row["floor"] = runs;
    row.update({{"speedup", 1.0}, {"ssim", 0.99}, {"flip", 0.01}, {"psnr_db", 40.0}, {"fpsnr_db", nullptr}});
    report["rows"].push_back(row);
    for (const PlannedCell& planned : layout.unit_cells) {
      nlohmann::json cell = key;
      cell["method"] = bench_method_name(planned.method);
      cell["unit"] = unit;
      if (planned.refresh) cell.update({{"refresh", *planned.refresh}, {"fovea_deg", *planned.fovea_deg}});
      if (planned.focal_share_x)
        cell.update({{"focal_share_x", *planned.focal_share_x}, {"focal_share_y", *planned.focal_share_y}});
      cell.update(runs);
      cell.update({{"gt_median_gpu_ms", 2.0},
                   {"speedup", 1.0},
                   {"top_level_share", 1.0},
                   {"refreshed_share", 0.0},
                   {"ssim", 0.99},
                   {"flip", 0.01},
                   {"psnr_db", nullptr},
                   {"fpsnr_db", 40.0}});
      report["cells"].push_back(cell);
    }
  }
  return report;
}

// Part `index` of `count` cut from the whole sweep, as bench --cells writes it.
PartReport part_of(const nlohmann::json& whole, int index, int count) {
  const int units = int(whole["rows"].size());
  const SweepPart part{index, count};
  nlohmann::json report = whole;
  report["rows"] = nlohmann::json::array();
  report["cells"] = nlohmann::json::array();
  const size_t cells_per_unit = whole["cells"].size() / whole["rows"].size();
  for (int unit = 0; unit < units; ++unit) {
    if (!part.holds(unit)) continue;
    report["rows"].push_back(whole["rows"][size_t(unit)]);
    for (size_t cell = size_t(unit) * cells_per_unit; cell < size_t(unit + 1) * cells_per_unit; ++cell)
      report["cells"].push_back(whole["cells"][cell]);
  }
  report["part"] = part_json(part, units);
  return {"part-" + std::to_string(index) + ".json", report};
}

std::string error_of(const std::vector<PartReport>& parts, const SweepLayout& layout = layout_of(5)) {
  try {
    merge_bench_parts(parts, [&](const PartReport&) { return layout; });
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(BenchParts, UnitsInterleaveAndCountsAddUp) {
  for (int count = 1; count <= 7; ++count) {
    int held = 0;
    for (int index = 0; index < count; ++index) {
      const SweepPart part{index, count};
      int mine = 0;
      for (int unit = 0; unit < 5; ++unit) mine += part.holds(unit);
      EXPECT_EQ(part.units_held(5), mine) << index << "/" << count;
      held += mine;
    }
    EXPECT_EQ(held, 5) << count;
  }
}

TEST(BenchParts, MergedPartsAreTheWholeSweepInAnyOrder) {
  const SweepLayout layout = layout_of(5);
  const nlohmann::json whole = whole_sweep(layout);
  for (int count : {1, 2, 3, 5, 7}) {  // 7: two parts hold nothing
    std::vector<PartReport> parts;
    for (int index = count - 1; index >= 0; --index) parts.push_back(part_of(whole, index, count));
    EXPECT_EQ(merge_bench_parts(parts, [&](const PartReport&) { return layout; }), whole) << count << " parts";
  }
}

TEST(BenchParts, MissingRepeatedOrForeignPartsAreRefusedNamingThem) {
  const nlohmann::json whole = whole_sweep(layout_of(5));
  const PartReport p0 = part_of(whole, 0, 3), p1 = part_of(whole, 1, 3), p2 = part_of(whole, 2, 3);
  EXPECT_NE(error_of({p0, p2}).find("part 1/3 missing (2 of 3 given)"), std::string::npos) << error_of({p0, p2});
  EXPECT_NE(error_of({p0}).find("parts 1/3, 2/3 missing"), std::string::npos) << error_of({p0});
  PartReport again = p1;
  again.path = "copy.json";
  EXPECT_NE(error_of({p0, p1, again, p2}).find("copy.json: part 1/3 again (also part-1.json)"), std::string::npos)
      << error_of({p0, p1, again, p2});
  // Parts of a sweep cut into another count, or of another sweep or device.
  EXPECT_NE(
      error_of({p0, part_of(whole, 1, 2), p2}).find("part-1.json: part 1/2 of 5 units, but part-0.json is of 3 parts"),
      std::string::npos);
  PartReport other_device = p2;
  other_device.report["device"] = "another GPU";
  EXPECT_NE(error_of({p0, p1, other_device}).find("part-2.json: \"device\" differs from part-0.json's"),
            std::string::npos)
      << error_of({p0, p1, other_device});
  PartReport extra_key = p1;
  extra_key.report["height"] = 48;
  EXPECT_NE(error_of({p0, extra_key, p2}).find("\"height\""), std::string::npos);
  PartReport missing_key = p1;
  missing_key.report.erase("width");
  EXPECT_NE(error_of({p0, missing_key, p2}).find("part-1.json: width is missing or not a number"), std::string::npos);
  PartReport new_key = p1;
  new_key.report["extra"] = 1;
  EXPECT_NE(error_of({p0, new_key, p2}).find("part-1.json: \"extra\" differs from part-0.json's"), std::string::npos);
  // Rows and cells that are not the part's units.
  PartReport short_rows = p0;
  short_rows.report["rows"].erase(0);
  EXPECT_NE(error_of({short_rows, p1, p2}).find("part-0.json: 1 rows; expected 2"), std::string::npos)
      << error_of({short_rows, p1, p2});
  PartReport odd_cells = p0;
  odd_cells.report["cells"].erase(0);
  EXPECT_NE(error_of({odd_cells, p1, p2}).find("part-0.json: 3 cells for 2 units"), std::string::npos);
  PartReport swapped = p0;
  std::swap(swapped.report["cells"][0], swapped.report["cells"][2]);
  EXPECT_NE(error_of({swapped, p1, p2}).find("is not its unit's"), std::string::npos) << error_of({swapped, p1, p2});
  // Not parts at all.
  PartReport whole_run{"whole.json", whole};
  EXPECT_NE(error_of({whole_run}).find("whole.json: not a part of a sweep"), std::string::npos);
  PartReport bad_index = p0;
  bad_index.report["part"]["index"] = 3;
  EXPECT_NE(error_of({bad_index}).find("expected 0 <= index < count"), std::string::npos);
  PartReport no_units = p0;
  no_units.report["part"].erase("units");
  EXPECT_NE(error_of({no_units}).find("\"part\".units is not a whole number"), std::string::npos);
  PartReport huge = p0;
  huge.report["part"]["count"] = 2000000000;
  EXPECT_NE(error_of({huge}).find("count <= 100000"), std::string::npos);
  // A unit's fields the tables read: missing or of the wrong kind, named.
  PartReport no_ssim = p1;
  no_ssim.report["cells"][1].erase("ssim");
  EXPECT_NE(error_of({p0, no_ssim, p2}).find("part-1.json: cells[1].ssim is missing or not a number"),
            std::string::npos)
      << error_of({p0, no_ssim, p2});
  PartReport text_ms = p1;
  text_ms.report["rows"][0]["gt"]["median_gpu_ms"] = "fast";
  EXPECT_NE(error_of({p0, text_ms, p2}).find("part-1.json: rows[0].gt.median_gpu_ms is missing or not a number"),
            std::string::npos)
      << error_of({p0, text_ms, p2});
  PartReport no_device = p1;
  no_device.report.erase("device");
  EXPECT_NE(error_of({p0, no_device, p2}).find("part-1.json: device is missing or not text"), std::string::npos);
  PartReport text_index = p0;
  text_index.report["part"]["index"] = "0";
  EXPECT_NE(error_of({text_index}).find("\"part\".index is not a whole number"), std::string::npos);
  EXPECT_NE(error_of({}).find("no parts given"), std::string::npos);
}

// Each part is held to the sweep its flags plan: a part relabelled to another index (its rows are
// another part's units) is refused naming the row's field, even where the row counts agree.
TEST(BenchParts, APartsUnitsAreThoseOfItsIndexInThePlannedSweep) {
  const SweepLayout two_spps = layout_of(2, {1, 4});  // units (s0, 1), (s0, 4), (s1, 1), (s1, 4)
  const nlohmann::json whole = whole_sweep(two_spps);
  PartReport p0 = part_of(whole, 0, 2), p1 = part_of(whole, 1, 2);
  std::swap(p0.report["part"], p1.report["part"]);  // part-0.json now says it is 1/2, part-1.json 0/2
  EXPECT_NE(error_of({p0, p1}, two_spps)
                .find("part-1.json: rows[0].spp is 4; expected 1 (unit 0 of the sweep: part 0/2 "
                      "holds units 0, 0 + 2, ..."),
            std::string::npos)
      << error_of({p0, p1}, two_spps);

  const SweepLayout five = layout_of(5);  // in 4 parts, parts 1, 2 and 3 hold one unit each
  const nlohmann::json five_whole = whole_sweep(five);
  std::vector<PartReport> parts;
  for (int index = 0; index < 4; ++index) parts.push_back(part_of(five_whole, index, 4));
  std::swap(parts[1].report["part"], parts[2].report["part"]);
  EXPECT_NE(error_of(parts, five).find("part-2.json: rows[0].scene is \"s2\"; expected \"s1\" (unit 1 of the sweep"),
            std::string::npos)
      << error_of(parts, five);

  // The part's "units" and settings are the planned sweep's.
  EXPECT_NE(error_of({part_of(whole_sweep(five), 0, 1)}, layout_of(6))
                .find("part-0.json: \"part\".units is 5; expected 6, the sweep's 6 scenes x 1 times x 1 spp"),
            std::string::npos)
      << error_of({part_of(whole_sweep(five), 0, 1)}, layout_of(6));
  SweepLayout narrower = five;
  narrower.width = 32;
  EXPECT_NE(error_of({part_of(five_whole, 0, 1)}, narrower).find("part-0.json: width is 64; expected 32"),
            std::string::npos);
}

// A cell's method and variant are the plan's: a method that no flag planned ("xyz", or a real one
// in another place), a FIPR variant or RMFR pair that differs, are refused naming the cell's field.
TEST(BenchParts, ACellsMethodAndVariantAreThePlannedOnes) {
  const SweepLayout layout = layout_of(3);
  const nlohmann::json whole = whole_sweep(layout);
  const PartReport p0 = part_of(whole, 0, 2), p1 = part_of(whole, 1, 2);
  PartReport xyz = p1;
  xyz.report["cells"][1]["method"] = "xyz";
  EXPECT_NE(error_of({p0, xyz}, layout)
                .find("part-1.json: cells[1].method is \"xyz\"; expected \"ipr\" (cell 2 of "
                      "every unit's 2: gt, ipr"),
            std::string::npos)
      << error_of({p0, xyz}, layout);
  PartReport swapped = p0;
  std::swap(swapped.report["cells"][0]["method"], swapped.report["cells"][1]["method"]);
  EXPECT_NE(error_of({swapped, p1}, layout).find("cells[0].method is \"ipr\"; expected \"gt\""), std::string::npos);

  SweepLayout variants = layout;
  variants.unit_cells = {{BenchMethod::gt},
                         {BenchMethod::fipr, 2, 7.5, std::nullopt, std::nullopt},
                         {bench_method_of(SamplingModel::rectangular), std::nullopt, std::nullopt, 0.3, 0.55}};
  variants.focal_shares_x = {0.3};
  variants.focal_shares_y = {0.55};
  const nlohmann::json variant_whole = whole_sweep(variants);
  EXPECT_EQ(error_of({part_of(variant_whole, 0, 1)}, variants), "");
  // What the tables group cells by is the plan's too: scene times, FIPR, RMFR's pairs.
  PartReport other_times = part_of(variant_whole, 0, 1);
  other_times.report["times_s"] = {0.0, 9.0};
  EXPECT_NE(error_of({other_times}, variants).find("part-0.json: times_s is [0.0,9.0]; expected [0.0]"),
            std::string::npos)
      << error_of({other_times}, variants);
  PartReport no_fipr = part_of(variant_whole, 0, 1);
  no_fipr.report.erase("fipr");
  EXPECT_NE(error_of({no_fipr}, variants).find("part-0.json: no \"fipr\" object; expected one"), std::string::npos)
      << error_of({no_fipr}, variants);
  PartReport text_shares = part_of(variant_whole, 0, 1);
  text_shares.report["sampling_focal_shares"] = "0.3";
  EXPECT_NE(
      error_of({text_shares}, variants).find("part-0.json: sampling_focal_shares is \"0.3\"; expected {\"x\":[0.3],"),
      std::string::npos)
      << error_of({text_shares}, variants);
  PartReport other_fovea = part_of(variant_whole, 0, 1);
  other_fovea.report["cells"][4]["fovea_deg"] = 5.0;
  EXPECT_NE(error_of({other_fovea}, variants)
                .find("part-0.json: cells[4].fovea_deg is 5.0; expected 7.5 (cell 2 of "
                      "every unit's 3: gt, fipr, rmfr"),
            std::string::npos)
      << error_of({other_fovea}, variants);
  PartReport other_pair = part_of(variant_whole, 0, 1);
  other_pair.report["cells"][2].erase("focal_share_y");
  other_pair.report["cells"][2].erase("focal_share_x");
  EXPECT_NE(error_of({other_pair}, variants).find("cells[2].focal_share_x is missing; expected 0.3"), std::string::npos)
      << error_of({other_pair}, variants);
}

// Times are GPU milliseconds of a frame: from 0 to a day; ratios and counts at least 0. Messages
// quote the part's own numbers (exact integers, however large).
TEST(BenchParts, TimesOutOfRangeAndHugeNumbersAreRefusedAsWritten) {
  const SweepLayout layout = layout_of(3);
  const nlohmann::json whole = whole_sweep(layout);
  const PartReport p0 = part_of(whole, 0, 2), p1 = part_of(whole, 1, 2);
  const auto refused = [&](const char* what, nlohmann::json::json_pointer at, const nlohmann::json& value,
                           const std::string& expected) {
    PartReport edited = p1;
    edited.report[at] = value;
    EXPECT_NE(error_of({p0, edited}, layout).find(expected), std::string::npos)
        << what << ": " << error_of({p0, edited}, layout);
  };
  const std::string time = "; expected a GPU time in milliseconds from 0 to 86400000 (a day)";
  refused("negative", "/cells/1/median_gpu_ms"_json_pointer, -5.0,
          "part-1.json: cells[1].median_gpu_ms is -5.0" + time);
  refused("huge", "/rows/0/gt/median_gpu_ms"_json_pointer, 1e308,
          "part-1.json: rows[0].gt.median_gpu_ms is 1e+308" + time);
  refused("GT's in a cell", "/cells/0/gt_median_gpu_ms"_json_pointer, 1e308,
          "cells[0].gt_median_gpu_ms is 1e+308" + time);
  refused("a pass", "/rows/0/ipr/median_pass_gpu_ms/trace_level0"_json_pointer, -1,
          "rows[0].ipr.median_pass_gpu_ms.trace_level0 is -1" + time);
  refused("a cell's pass", "/cells/1/median_pass_gpu_ms/trace_level0"_json_pointer, 1e300,
          "cells[1].median_pass_gpu_ms.trace_level0 is 1e+300" + time);
  refused("the floor", "/rows/0/floor/median_gpu_ms"_json_pointer, 86400000.5,
          "rows[0].floor.median_gpu_ms is 86400000.5" + time);
  refused("a speed-up", "/cells/1/speedup"_json_pointer, -2.0,
          "cells[1].speedup is -2.0; expected a finite number of at least 0");
  refused("capped rays", "/rows/0/gt/capped_rays"_json_pointer, -1,
          "rows[0].gt.capped_rays is -1; expected a whole number of rays, at least 0");
  // 10^18 is quoted as written, never narrowed to a negative int.
  PartReport far = p0;
  far.report["part"]["index"] = 1000000000000000000;
  EXPECT_NE(
      error_of({far, p1}, layout).find("part-0.json: \"part\" 1000000000000000000/2 of 3 units; expected 0 <= index"),
      std::string::npos)
      << error_of({far, p1}, layout);
  far.report["part"]["index"] = 18446744073709551615u;
  EXPECT_NE(error_of({far, p1}, layout).find("\"part\" 18446744073709551615/2 of 3 units"), std::string::npos)
      << error_of({far, p1}, layout);
  PartReport many = p1;
  many.report["part"]["count"] = -1000000000000000000;
  EXPECT_NE(error_of({p0, many}, layout).find("\"part\" 1/-1000000000000000000 of 3 units"), std::string::npos)
      << error_of({p0, many}, layout);
  // An edge that is allowed: a time of 0 (a frame under the timer's resolution) and of exactly a day.
  PartReport edges = p1;
  edges.report["cells"][1]["median_gpu_ms"] = 0.0;
  edges.report["rows"][0]["floor"]["median_gpu_ms"] = 86400000.0;
  EXPECT_EQ(error_of({p0, edges}, layout), "");
}

}  // namespace
}  // namespace fovlab::bench
