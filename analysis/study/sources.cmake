# analysis/study: sources of fovlab_analysis and their tests (paths from the repository root).
list(APPEND analysis_sources
  ${CMAKE_SOURCE_DIR}/analysis/study/study_data.cpp
  ${CMAKE_SOURCE_DIR}/analysis/study/study_analysis.cpp
  ${CMAKE_SOURCE_DIR}/analysis/study/rating_grid.cpp
  ${CMAKE_SOURCE_DIR}/analysis/study/preference_table.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/study/study_analysis_test.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/study/pilot_recovery_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/analysis/study/protocol_recovery_test.cpp)
list(APPEND analysis_tests ${CMAKE_SOURCE_DIR}/tests/analysis/study/analyze_cli_test.cpp)
list(APPEND analysis_tests ${CMAKE_SOURCE_DIR}/tests/analysis/study/rating_grid_preference_test.cpp)
