# protocols/stimuli: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/study/stimulus/stimulus_spec.cpp)
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/stimuli/stimulus_library.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/stimuli/fipr_stimulus_test.cpp)
