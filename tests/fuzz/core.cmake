# Core loaders and converters: files users write (scenes, payloads, robots, meshes, trajectory
# JSON) and the trajectory message porter-tracker receives.
porter_add_fuzz_target(trajectory_json SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_trajectory_json.cpp
  LIBS porter::core_io MAX_LEN 8192 RUNS 20000)
porter_add_fuzz_target(trajectory_msg SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_trajectory_msg.cpp
  LIBS porter::msg MAX_LEN 8192 RUNS 20000)
porter_add_fuzz_target(mesh_loader SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_mesh_loader.cpp
  LIBS porter::core_io MAX_LEN 16384 RUNS 5000)
porter_add_fuzz_target(scene_loader SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_scene_loader.cpp
  LIBS porter::core_io MAX_LEN 8192 RUNS 5000)
porter_add_fuzz_target(payload_loader SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_payload_loader.cpp
  LIBS porter::core_io MAX_LEN 4096 RUNS 5000)
porter_add_fuzz_target(robot_loader SOURCE ${CMAKE_CURRENT_LIST_DIR}/fuzz_robot_loader.cpp
  LIBS porter::core_io MAX_LEN 16384 RUNS 2000)
foreach(_target porter-fuzz-robot_loader porter-fuzz-random-robot_loader porter-fuzz-payload_loader
                porter-fuzz-random-payload_loader)
  if(TARGET ${_target})
    target_compile_definitions(${_target} PRIVATE PORTER_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  endif()
endforeach()
