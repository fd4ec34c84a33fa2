# The LCM guard (porter/lcm_guard.hpp) of every message type: one target per type, named
# lcm_<type>, seeds in corpus/lcm_<type>/ (tests/fuzz/make_lcm_corpus.py).
foreach(_type IN LISTS PORTER_LCM_TYPE_NAMES)
  porter_add_fuzz_target(lcm_${_type} SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_lcm_guard.cpp
    LIBS porter::lcmtypes MAX_LEN 1024 RUNS 20000)
  foreach(_target porter-fuzz-lcm_${_type} porter-fuzz-random-lcm_${_type})
    if(TARGET ${_target})
      target_compile_definitions(${_target} PRIVATE PORTER_FUZZ_LCM_TYPE=${_type})
    endif()
  endforeach()
endforeach()
