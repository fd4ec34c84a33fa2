# Runs `scripts/spy --check --jar JAR` and checks it succeeds and lists every type in TYPES.
# Invoked by CTest: cmake -DSPY=... -DJAR=... -DTYPES=a;b;c -P spy_check.cmake
if(NOT EXISTS "${JAR}")
  message(FATAL_ERROR "${JAR} does not exist: build the porter_lcmtypes_jar target first")
endif()
execute_process(
  COMMAND "${SPY}" --check --jar "${JAR}"
  RESULT_VARIABLE rc
  OUTPUT_VARIABLE out
  ERROR_VARIABLE err)
message(STATUS "scripts/spy --check output:\n${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "scripts/spy --check failed with ${rc}")
endif()
foreach(type IN LISTS TYPES)
  string(FIND "${out}" "  porter.${type}\n" pos)
  if(pos EQUAL -1)
    message(FATAL_ERROR "scripts/spy --check does not list porter.${type}")
  endif()
endforeach()
