# protocols/presentation: sources of fovlab_protocols and their tests (paths from the repository root).
list(APPEND protocols_sources
  ${CMAKE_SOURCE_DIR}/protocols/presentation/frame_io.cpp
  ${CMAKE_SOURCE_DIR}/protocols/presentation/glfw_input.cpp
  ${CMAKE_SOURCE_DIR}/protocols/presentation/text_screen.cpp
  ${CMAKE_SOURCE_DIR}/protocols/presentation/window_presenter.cpp)
list(APPEND protocols_tests
  ${CMAKE_SOURCE_DIR}/tests/protocols/presentation/text_screen_test.cpp
  ${CMAKE_SOURCE_DIR}/tests/protocols/presentation/window_presenter_test.cpp)

# Window tests skip without a display (gtest_discover_tests runs them as they are), so an extra
# CTest entry runs the tests matching `filter` again under a virtual X server (Debian: xvfb xauth),
# with the validation layer on; FOVLAB_REQUIRE_DISPLAY=1 turns a missing display into a failure
# there. Called at the end of the top CMakeLists.txt, after fovlab_tests exists.
function(fovlab_add_xvfb_test name filter)
  find_program(FOVLAB_XVFB_RUN xvfb-run)
  if(NOT FOVLAB_XVFB_RUN)
    message(WARNING "xvfb-run not found (Debian: xvfb xauth): the window tests run only where DISPLAY is set")
    return()
  endif()
  add_test(NAME ${name}
    COMMAND ${FOVLAB_XVFB_RUN} -a -s "-screen 0 1280x720x24"
            $<TARGET_FILE:fovlab_tests> --gtest_filter=${filter})
  set_tests_properties(${name} PROPERTIES
    ENVIRONMENT "FOVLAB_VALIDATION=1;FOVLAB_REQUIRE_DISPLAY=1;FOVLAB_SHADER_CACHE=${CMAKE_BINARY_DIR}/test-shader-cache"
    TIMEOUT 120
    # xvfb-run -a picks a free display by a racy lock-file check: tests that share this lock
    # never start two virtual servers at once.
    RESOURCE_LOCK xvfb)
endfunction()
