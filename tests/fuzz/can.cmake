# CAN transports: the decoders of bytes that arrive from outside (adapter lines, controller
# error frames).
porter_add_fuzz_target(slcan_lines SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_slcan_lines.cpp
  LIBS porter::can MAX_LEN 512 RUNS 20000)
porter_add_fuzz_target(can_error_frame SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_can_error_frame.cpp
  LIBS porter::can MAX_LEN 16 RUNS 20000)
