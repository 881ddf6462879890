#include "analysis/report/report.h"

#include <filesystem>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include "analysis/report/report_formats.h"
#include "core/atomic_file.h"
#include "core/input_error.h"

namespace fovlab::analysis {

namespace fs = std::filesystem;

std::vector<std::string> write_analysis_report(const AnalysisResult& result, const std::string& out_dir) {
  const fs::path dir(out_dir);
  fs::create_directories(dir);
  std::vector<std::string> written;
  auto write = [&](const std::string& name, const std::string& text) {
    const fs::path path = dir / name;
    write_text_atomically(path, text);
    written.push_back(path.string());
  };

  write("headline.csv", report_detail::headline_csv(result));
  write("conditions.csv", report_detail::conditions_csv(result));
  write("participants.csv", report_detail::participants_csv(result));
  if (report_detail::has_adaptive_tracks(result))
    write("adaptive_tracks.csv", report_detail::adaptive_tracks_csv(result));
  if (result.rating_grid) write("rating_grid.csv", report_detail::rating_grid_csv(*result.rating_grid, result.study));
  if (!result.preferences.empty()) write("preference.csv", report_detail::preference_csv(result));
  write("thresholds.json", report_detail::thresholds_json_text(result));

  const report_detail::ReportPlots plots = report_detail::report_plots(result);
  for (const report_detail::Plot& plot : plots.figures) write(plot.file_name, plot.svg);
  for (const report_detail::Plot& plot : plots.frame_intervals) write(plot.file_name, plot.svg);

  write("report.html", report_detail::report_html(result, plots));
  return written;
}

namespace {

// A name write_analysis_report writes, or the temporary of one (".<stem>.tmp-<pid>.<ext>", left
// inside by a run killed before this folder-level writing existed).
bool is_report_file_name(const std::string& name) {
  if (name == "thresholds.json" || name == "headline.csv" || name == "conditions.csv" || name == "participants.csv" ||
      name == "report.html" || name == "rating_grid.csv" || name == "preference.csv" || name == "adaptive_tracks.csv")
    return true;
  const auto ends_with = [&](const std::string& end) {
    return name.size() > end.size() && name.compare(name.size() - end.size(), end.size(), end) == 0;
  };
  if (name[0] == '.' && name.find(".tmp-") != std::string::npos) return true;
  return ends_with(".svg");
}

}  // namespace

void check_analysis_destination(const std::string& out_dir, bool replace) {
  const fs::path dir(out_dir);
  remove_stale_folder_temporaries(dir);
  std::error_code error;
  const fs::file_status status = fs::symlink_status(dir, error);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) throw InputError(out_dir + ": is not a folder; give --out a folder for the analysis");
  bool has_thresholds = false;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file() || entry.is_symlink() || !is_report_file_name(name))
      throw InputError(out_dir + ": holds " + name +
                       ", which fovlab analyze does not write; give --out another folder (--force replaces only an "
                       "earlier analysis)");
    has_thresholds = has_thresholds || name == "thresholds.json";
  }
  if (!has_thresholds && !fs::is_empty(dir))
    throw InputError(out_dir + ": holds files but no thresholds.json (not an analysis); give --out another folder");
  if (has_thresholds && !replace)
    throw InputError(out_dir + ": an analysis is already there; add --force to replace it");
}

std::vector<std::string> write_analysis_folder(const AnalysisResult& result, const std::string& out_dir, bool replace) {
  check_analysis_destination(out_dir, replace);
  std::vector<std::string> written;
  write_folder_atomically(out_dir, replace, [&](const fs::path& temporary) {
    for (const std::string& path : write_analysis_report(result, temporary.string()))
      written.push_back((fs::path(out_dir) / fs::path(path).filename()).string());
  });
  return written;
}

}  // namespace fovlab::analysis
