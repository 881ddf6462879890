# analysis/study: sources of fovlab_analysis and their tests (paths from the repository root).
list(APPEND analysis_sources
  ${CMAKE_SOURCE_DIR}/analysis/study/study_data.cpp
  ${CMAKE_SOURCE_DIR}/analysis/study/study_analysis.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/study/study_analysis_test.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/study/pilot_recovery_test.cpp)
list(APPEND analysis_tests ${CMAKE_SOURCE_DIR}/tests/analysis/study/analyze_cli_test.cpp)
