# porter-mapper: its LCM inputs (ROBOT_STATE, LIDAR_POINTS) through the process's node.
porter_add_fuzz_target(mapper_inputs SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_mapper_inputs.cpp
  LIBS porter_mapper_app_support octomap MAX_LEN 4096 RUNS 20000)
