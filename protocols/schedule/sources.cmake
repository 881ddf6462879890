# protocols/schedule: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/schedule/study_plan.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/schedule/study_plan_test.cpp)
