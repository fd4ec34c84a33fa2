# porter-planner: its LCM inputs (OctoMap streams, goals, robot states) through the adapter.
porter_add_fuzz_target(planner_inputs SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_planner_inputs.cpp
  LIBS porter_planner_app_support MAX_LEN 4096 RUNS 5000)
