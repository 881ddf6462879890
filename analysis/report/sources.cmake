# analysis/report: sources of fovlab_analysis and their tests (paths from the repository root).
list(APPEND analysis_sources
  ${CMAKE_SOURCE_DIR}/analysis/report/svg_chart.cpp
  ${CMAKE_SOURCE_DIR}/analysis/report/report.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/report/svg_chart_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/analysis/report/report_test.cpp)
