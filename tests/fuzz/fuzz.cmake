# Fuzzing the parsers of what users give fovlab (tests/fuzz/*_fuzz.cpp): study configs, session
# logs, gaze traces and OBJ meshes. Included at the end of tests/CMakeLists.txt, after
# fovlab_tests exists.
#
# Every build: fovlab_<name>_corpus replays the checked-in corpus (tests/fuzz/corpus/<name>)
# through the same harness without libFuzzer, as the CTest entry FuzzCorpus.<name>.
#
# -DFOVLAB_FUZZ=ON (clang only; scripts/fuzz configures build/fuzz this way): also the libFuzzer
# targets fovlab_<name>_fuzz. The rest of the project must be instrumented too, which this late
# include cannot arrange for targets already defined: pass
# -DCMAKE_CXX_FLAGS="-fsanitize=address,undefined,fuzzer-no-link" (scripts/fuzz does).
option(FOVLAB_FUZZ "Build the libFuzzer targets fovlab_<name>_fuzz (clang; see scripts/fuzz)" OFF)

set(fovlab_fuzz_dir ${CMAKE_SOURCE_DIR}/tests/fuzz)
# Harness name and the library it needs: the OBJ loader is in fovlab_renderer (parse only, no
# Vulkan device is made), the gaze trace in fovlab_protocols, configs and logs in fovlab_study.
set(fovlab_fuzz_harnesses config log gaze_trace obj)
set(fovlab_fuzz_library_config fovlab_study)
set(fovlab_fuzz_library_log fovlab_study)
set(fovlab_fuzz_library_gaze_trace fovlab_protocols)
set(fovlab_fuzz_library_obj fovlab_renderer)

foreach(fovlab_fuzz_name ${fovlab_fuzz_harnesses})
  add_executable(fovlab_${fovlab_fuzz_name}_corpus
    ${fovlab_fuzz_dir}/corpus_runner.cpp
    ${fovlab_fuzz_dir}/${fovlab_fuzz_name}_fuzz.cpp)
  target_link_libraries(fovlab_${fovlab_fuzz_name}_corpus PRIVATE ${fovlab_fuzz_library_${fovlab_fuzz_name}} fovlab_warnings)
  add_test(NAME FuzzCorpus.${fovlab_fuzz_name}
    COMMAND fovlab_${fovlab_fuzz_name}_corpus ${fovlab_fuzz_dir}/corpus/${fovlab_fuzz_name})
  set_tests_properties(FuzzCorpus.${fovlab_fuzz_name} PROPERTIES
    ENVIRONMENT "FOVLAB_VALIDATION=1"
    TIMEOUT 120)
endforeach()

if(FOVLAB_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "FOVLAB_FUZZ=ON needs clang (libFuzzer); configure with CXX=clang++ (scripts/fuzz does)")
  endif()
  if(NOT CMAKE_CXX_FLAGS MATCHES "fuzzer-no-link" OR NOT CMAKE_CXX_FLAGS MATCHES "address")
    message(FATAL_ERROR "FOVLAB_FUZZ=ON: the whole project must be instrumented; configure with "
                        "-DCMAKE_CXX_FLAGS=\"-fsanitize=address,undefined,fuzzer-no-link\" (scripts/fuzz does)")
  endif()
  # Debian's toml++ is a prebuilt shared library (-DTOML_HEADER_ONLY=0), compiled without coverage
  # or sanitizers: the TOML parser, the bulk of the config parsing, would be invisible to the
  # fuzzer. In this build use its header-only mode instead, so it is compiled (and instrumented)
  # into fovlab_study; its inline definitions take precedence over the shared library's.
  if(TARGET tomlplusplus::tomlplusplus)
    set_property(TARGET tomlplusplus::tomlplusplus PROPERTY INTERFACE_COMPILE_OPTIONS -DTOML_HEADER_ONLY=1)
  endif()
  # The same for tinyobjloader (a prebuilt libtinyobjloader.so): its implementation is compiled
  # into fovlab_renderer here, and these definitions take precedence over the shared library's.
  # Third-party code: its warnings are not ours to fix.
  target_sources(fovlab_renderer PRIVATE ${fovlab_fuzz_dir}/tinyobjloader_instrumented.cpp)
  set_source_files_properties(${fovlab_fuzz_dir}/tinyobjloader_instrumented.cpp PROPERTIES COMPILE_OPTIONS -w)
  foreach(fovlab_fuzz_name ${fovlab_fuzz_harnesses})
    add_executable(fovlab_${fovlab_fuzz_name}_fuzz ${fovlab_fuzz_dir}/${fovlab_fuzz_name}_fuzz.cpp)
    target_link_libraries(fovlab_${fovlab_fuzz_name}_fuzz PRIVATE ${fovlab_fuzz_library_${fovlab_fuzz_name}} fovlab_warnings)
    target_compile_options(fovlab_${fovlab_fuzz_name}_fuzz PRIVATE -fsanitize=fuzzer,address,undefined)
    target_link_options(fovlab_${fovlab_fuzz_name}_fuzz PRIVATE -fsanitize=fuzzer,address,undefined)
  endforeach()
endif()
