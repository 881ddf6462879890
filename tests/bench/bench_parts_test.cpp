// A sweep in parts (bench/bench_parts.h): part I of N holds units I, I + N, ...; merging the parts
// gives back the whole sweep's rows and cells in order, whatever order the parts come in, and refuses
// a missing part, a part given twice, parts of another sweep, and a part whose rows or cells are not
// its units'.
#include "bench/bench_parts.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/input_error.h"

namespace fovlab::bench {
namespace {

// A sweep of `units` units (scene "s<unit / 2>", spp 1 or 4), two cells each (gt and ipr): the report
// one run would write, with the unit's number in each row and cell.
nlohmann::json whole_sweep(int units) {
  nlohmann::json report = {{"device", "test device"}, {"width", 64},           {"height", 36},
                           {"repeats", 1},            {"times_s", {0.0}},     {"command", "fovlab bench ..."},
                           {"metrics", {{"flip_pixels_per_degree", 1.3}}}};
  const nlohmann::json runs = {{"median_gpu_ms", 2.0}, {"steps_per_pixel", 9.5}, {"capped_rays", 0},
                               {"median_pass_gpu_ms", {{"trace_level0", 2.0}}}};
  report["rows"] = nlohmann::json::array();
  report["cells"] = nlohmann::json::array();
  for (int unit = 0; unit < units; ++unit) {
    const nlohmann::json key = {{"scene", "s" + std::to_string(unit / 2)}, {"spp", unit % 2 ? 4 : 1}, {"time_s", 0.0}};
    nlohmann::json row = key;
    row["unit"] = unit;
    row["gt"] = runs;
    row["ipr"] = runs;
    row["floor"] = runs;
    row.update({{"speedup", 1.0}, {"ssim", 0.99}, {"flip", 0.01}, {"psnr_db", 40.0}, {"fpsnr_db", nullptr}});
    report["rows"].push_back(row);
    for (const char* method : {"gt", "ipr"}) {
      nlohmann::json cell = key;
      cell["method"] = method;
      cell["unit"] = unit;
      cell.update(runs);
      cell.update({{"gt_median_gpu_ms", 2.0}, {"speedup", 1.0}, {"top_level_share", 1.0}, {"refreshed_share", 0.0},
                   {"ssim", 0.99}, {"flip", 0.01}, {"psnr_db", nullptr}, {"fpsnr_db", 40.0}});
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
  for (int unit = 0; unit < units; ++unit) {
    if (!part.holds(unit)) continue;
    report["rows"].push_back(whole["rows"][size_t(unit)]);
    report["cells"].push_back(whole["cells"][size_t(2 * unit)]);
    report["cells"].push_back(whole["cells"][size_t(2 * unit + 1)]);
  }
  report["part"] = part_json(part, units);
  return {"part-" + std::to_string(index) + ".json", report};
}

std::string error_of(const std::vector<PartReport>& parts) {
  try {
    merge_bench_parts(parts);
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
  const nlohmann::json whole = whole_sweep(5);
  for (int count : {1, 2, 3, 5, 7}) {  // 7: two parts hold nothing
    std::vector<PartReport> parts;
    for (int index = count - 1; index >= 0; --index) parts.push_back(part_of(whole, index, count));
    EXPECT_EQ(merge_bench_parts(parts), whole) << count << " parts";
  }
}

TEST(BenchParts, MissingRepeatedOrForeignPartsAreRefusedNamingThem) {
  const nlohmann::json whole = whole_sweep(5);
  const PartReport p0 = part_of(whole, 0, 3), p1 = part_of(whole, 1, 3), p2 = part_of(whole, 2, 3);
  EXPECT_NE(error_of({p0, p2}).find("part 1/3 missing (2 of 3 given)"), std::string::npos) << error_of({p0, p2});
  EXPECT_NE(error_of({p0}).find("parts 1/3, 2/3 missing"), std::string::npos) << error_of({p0});
  PartReport again = p1;
  again.path = "copy.json";
  EXPECT_NE(error_of({p0, p1, again, p2}).find("copy.json: part 1/3 again (also part-1.json)"), std::string::npos)
      << error_of({p0, p1, again, p2});
  // Parts of a sweep cut into another count, or of another sweep or device.
  EXPECT_NE(error_of({p0, part_of(whole, 1, 2), p2}).find("part-1.json: part 1/2 of 5 units, but part-0.json is of 3 parts"),
            std::string::npos);
  PartReport other_device = p2;
  other_device.report["device"] = "another GPU";
  EXPECT_NE(error_of({p0, p1, other_device}).find("part-2.json: \"device\" differs from part-0.json's"), std::string::npos)
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
  EXPECT_NE(error_of({p0, no_ssim, p2}).find("part-1.json: cells[1].ssim is missing or not a number"), std::string::npos)
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

}  // namespace
}  // namespace fovlab::bench
