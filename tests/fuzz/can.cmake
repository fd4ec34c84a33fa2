porter_add_fuzz_target(can_frame_text SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_can_frame_text.cpp
  LIBS porter::can MAX_LEN 32 RUNS 20000)
