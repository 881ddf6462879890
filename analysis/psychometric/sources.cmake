# analysis/psychometric: sources of fovlab_analysis and their tests (paths from the repository root).
list(APPEND analysis_sources
  ${CMAKE_SOURCE_DIR}/analysis/psychometric/psychometric_function.cpp
  ${CMAKE_SOURCE_DIR}/analysis/psychometric/psychometric_fit.cpp
  ${CMAKE_SOURCE_DIR}/analysis/psychometric/binomial_sampler.cpp)
list(APPEND analysis_tests
  ${CMAKE_SOURCE_DIR}/tests/analysis/psychometric/psychometric_fit_test.cpp)
