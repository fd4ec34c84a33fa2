# porter-tracker and porter-state: their LCM inputs through the process adapters.
porter_add_fuzz_target(tracker_inputs SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_tracker_inputs.cpp
  LIBS porter_tracker_app_support MAX_LEN 2048 RUNS 20000)
porter_add_fuzz_target(state_inputs SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_state_inputs.cpp
  LIBS porter_state_app_support MAX_LEN 1024 RUNS 20000)
