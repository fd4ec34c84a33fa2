# Per-target defaults. No global flags: every Porter target calls porter_target_defaults().
function(porter_target_defaults target)
  target_compile_features(${target} PUBLIC cxx_std_17)
  set_target_properties(${target} PROPERTIES CXX_EXTENSIONS OFF POSITION_INDEPENDENT_CODE ON)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wno-unused-parameter)
  if(PORTER_SANITIZE)
    # ASan + UBSan on every Porter target (docs/hardening.md); a UBSan report fails the run.
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined
      -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# porter_add_test(name SOURCES a.cpp b.cpp LIBS x y)
# One GoogleTest executable; tests are discovered so CTest lists each TEST() separately.
function(porter_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LIBS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  porter_target_defaults(${name})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${name} PRIVATE PORTER_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "PORTER_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()

# porter_add_fuzz_target(name SOURCE fuzz_x.cpp LIBS x y [MAX_LEN n] [RUNS n])
# A fuzz target is one source file defining LLVMFuzzerTestOneInput for a decoder of outside
# bytes (CAN frames, serial lines, UDP packets, LCM messages, files). It is built twice:
# - always (with the tests): `porter-fuzz-random-<name>`, a CTest test that feeds the target its
#   seed corpus (tests/fuzz/corpus/<name>/ when present), mutations of the seeds and random
#   inputs, a bounded number of runs with a fixed seed (the suite's random-input test);
# - with -DPORTER_BUILD_FUZZ=ON under clang (scripts/fuzz): `porter-fuzz-<name>`, a libFuzzer
#   binary with ASan/UBSan, run for a bounded time by scripts/fuzz.
function(porter_add_fuzz_target name)
  cmake_parse_arguments(ARG "" "SOURCE;MAX_LEN;RUNS" "LIBS" ${ARGN})
  if(NOT ARG_MAX_LEN)
    set(ARG_MAX_LEN 4096)
  endif()
  if(NOT ARG_RUNS)
    set(ARG_RUNS 20000)
  endif()
  set(_corpus ${PROJECT_SOURCE_DIR}/tests/fuzz/corpus/${name})
  if(PORTER_BUILD_FUZZ)
    add_executable(porter-fuzz-${name} ${ARG_SOURCE})
    porter_target_defaults(porter-fuzz-${name})
    target_link_libraries(porter-fuzz-${name} PRIVATE ${ARG_LIBS})
    target_compile_options(porter-fuzz-${name} PRIVATE -fsanitize=fuzzer,${PORTER_FUZZ_SANITIZERS})
    target_link_options(porter-fuzz-${name} PRIVATE -fsanitize=fuzzer,${PORTER_FUZZ_SANITIZERS})
    set_target_properties(porter-fuzz-${name} PROPERTIES
      RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/fuzz)
  elseif(PORTER_BUILD_TESTS)
    add_executable(porter-fuzz-random-${name} ${ARG_SOURCE}
      ${PROJECT_SOURCE_DIR}/tests/fuzz/support/random_driver.cpp)
    porter_target_defaults(porter-fuzz-random-${name})
    target_link_libraries(porter-fuzz-random-${name} PRIVATE ${ARG_LIBS})
    add_test(NAME fuzz_random.${name}
      COMMAND porter-fuzz-random-${name} --runs ${ARG_RUNS} --max-len ${ARG_MAX_LEN}
              --corpus ${_corpus})
    set_tests_properties(fuzz_random.${name} PROPERTIES LABELS fuzz WORKING_DIRECTORY
      ${CMAKE_CURRENT_BINARY_DIR})
  endif()
endfunction()
