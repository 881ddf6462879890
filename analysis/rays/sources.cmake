# analysis/rays: sources of fovlab_analysis and their tests (paths from the repository root).
# rays_cli_test runs the built fovlab binary (`fovlab rays`, app/rays_command.cpp).
list(APPEND analysis_sources
  ${CMAKE_SOURCE_DIR}/analysis/rays/ray_count.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/rays/ray_count_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/analysis/rays/rays_cli_test.cpp)
