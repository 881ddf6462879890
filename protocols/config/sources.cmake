# protocols/config: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/config/toml_guard.cpp
  ${CMAKE_SOURCE_DIR}/protocols/config/toml_fields.cpp
  ${CMAKE_SOURCE_DIR}/protocols/config/input_keys.cpp
  ${CMAKE_SOURCE_DIR}/protocols/config/study_config.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/config/study_config_test.cpp)
list(APPEND protocols_tests ${CMAKE_SOURCE_DIR}/tests/protocols/config/toml_guard_test.cpp)
