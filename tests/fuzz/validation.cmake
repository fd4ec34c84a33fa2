porter_add_fuzz_target(plan_file SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_plan_file.cpp
  LIBS porter::validation MAX_LEN 2048 RUNS 20000)
