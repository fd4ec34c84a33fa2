# Piper protocol decoders, firmware model and driver logic on arbitrary CAN frames.
# Inputs are 12-byte records (tests/fuzz/piper_fuzz_input.hpp).
porter_add_fuzz_target(piper_feedback SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_piper_feedback.cpp
  LIBS porter::piper_protocol MAX_LEN 1200 RUNS 20000)
porter_add_fuzz_target(piper_command SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_piper_command.cpp
  LIBS porter::piper_protocol MAX_LEN 1200 RUNS 20000)
porter_add_fuzz_target(piper_firmware SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_piper_firmware.cpp
  LIBS porter::piper_firmware MAX_LEN 1200 RUNS 5000)
porter_add_fuzz_target(piper_driver SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_piper_driver.cpp
  LIBS porter::piper_driver MAX_LEN 1200 RUNS 5000)
