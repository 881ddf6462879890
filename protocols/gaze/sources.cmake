# protocols/gaze: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/gaze/gaze_sample.cpp
  ${CMAKE_SOURCE_DIR}/protocols/gaze/trace_gaze_source.cpp
  ${CMAKE_SOURCE_DIR}/protocols/gaze/synthetic_gaze_source.cpp
  ${CMAKE_SOURCE_DIR}/protocols/gaze/pupil_gaze_source.cpp
  ${CMAKE_SOURCE_DIR}/protocols/gaze/gaze_spec.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/gaze/fake_pupil_publisher.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/gaze/gaze_sample_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/gaze/trace_gaze_source_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/gaze/synthetic_gaze_source_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/gaze/pupil_gaze_source_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/gaze/gaze_spec_test.cpp)
# The fake Pupil Capture of the tests packs msgpack itself (fovlab_tests does not get the
# library's private definitions): header-only msgpack-cxx without Boost.
set_source_files_properties(${CMAKE_SOURCE_DIR}/tests/protocols/gaze/fake_pupil_publisher.cpp
  PROPERTIES COMPILE_DEFINITIONS MSGPACK_NO_BOOST)
