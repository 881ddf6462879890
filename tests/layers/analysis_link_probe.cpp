// A program that uses the whole analysis path (load logs, analyse, write the report) and links only
// fovlab_analysis: tests/layers/check_links.cmake checks that it needs no Vulkan, glslang, GLFW or
// ZeroMQ. Run with log paths and an output folder, it is a minimal `fovlab analyze`.
#include <cstdio>
#include <string>
#include <vector>

#include "analysis/report/report.h"
#include "analysis/study/study_analysis.h"
#include "analysis/study/study_data.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s OUT_DIR LOG...\n", argv[0]);
    return 2;
  }
  const std::vector<std::string> logs(argv + 2, argv + argc);
  const fovlab::analysis::StudyData data = fovlab::analysis::load_study(logs);
  const auto result = fovlab::analysis::analyse_study(data, {});
  fovlab::analysis::write_analysis_folder(result, argv[1], true);
  return 0;
}
