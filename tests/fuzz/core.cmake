# Core loaders and converters: files users write (scenes, payloads, robots, meshes, trajectory
# JSON) and the trajectory message porter-tracker receives.
porter_add_fuzz_target(trajectory_json SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_trajectory_json.cpp
  LIBS porter::core_io MAX_LEN 8192 RUNS 20000)
porter_add_fuzz_target(trajectory_msg SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_trajectory_msg.cpp
  LIBS porter::msg MAX_LEN 8192 RUNS 20000)
