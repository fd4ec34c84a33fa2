# Scout Mini: every decoder of frames from the base's bus, the driver's logic fed by them, and
# the firmware model fed by the driver's side of the bus.
porter_add_fuzz_target(scout_mini_driver SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_scout_mini_driver.cpp
  LIBS porter::scout_mini MAX_LEN 2400 RUNS 20000)
porter_add_fuzz_target(scout_mini_firmware
  SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_scout_mini_firmware.cpp
  LIBS porter::scout_mini_firmware MAX_LEN 2400 RUNS 10000)
