# Livox MID-360 datagrams (porter-lidar's UDP input): decoder, round trip, stream handling.
porter_add_fuzz_target(livox_packet SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_livox_packet.cpp
  LIBS porter::livox MAX_LEN 1500 RUNS 20000)
# The MID-360 command channel (porter-lidar reads ACKs, the simulated sensor reads requests).
porter_add_fuzz_target(livox_command SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_livox_command.cpp
  LIBS porter::livox MAX_LEN 1500 RUNS 20000)
