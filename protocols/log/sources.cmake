# protocols/log: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/log/event_log.cpp
  ${CMAKE_SOURCE_DIR}/protocols/log/log_integrity.cpp
  ${CMAKE_SOURCE_DIR}/protocols/log/participant_lock.cpp
  ${CMAKE_SOURCE_DIR}/protocols/log/session_record.cpp
  ${CMAKE_SOURCE_DIR}/protocols/log/session_scan.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/core_prng_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/log/event_log_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/log/session_scan_test.cpp)
