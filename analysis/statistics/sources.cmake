# analysis/statistics: sources of fovlab_analysis and their tests (paths from the repository root).
list(APPEND analysis_sources
  ${CMAKE_SOURCE_DIR}/analysis/statistics/binomial.cpp
  ${CMAKE_SOURCE_DIR}/analysis/statistics/multiple_comparisons.cpp
  ${CMAKE_SOURCE_DIR}/analysis/statistics/percentile.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/statistics/binomial_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/analysis/statistics/multiple_comparisons_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/analysis/statistics/percentile_test.cpp)
