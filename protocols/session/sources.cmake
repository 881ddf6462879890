# protocols/session: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/session/response_source.cpp
  ${CMAKE_SOURCE_DIR}/protocols/session/session_header.cpp
  ${CMAKE_SOURCE_DIR}/protocols/session/session_run.cpp
  ${CMAKE_SOURCE_DIR}/protocols/session/session.cpp
  ${CMAKE_SOURCE_DIR}/protocols/session/replay.cpp
  ${CMAKE_SOURCE_DIR}/protocols/session/trials_export.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/session_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/kill_resume_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/session_integrity_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/session_race_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/disk_full_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/windowed_session_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/fipr_session_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/session/latency_session_test.cpp)
