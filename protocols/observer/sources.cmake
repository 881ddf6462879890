# protocols/observer: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/observer/simulated_observer.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/observer/simulated_observer_test.cpp)
