# Tests of the robot model: kinematics against the Piper DH table, Jacobians, loaders, payloads.
porter_add_test(test_kinematics SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_kinematics.cpp
  LIBS porter::core porter::core_io)
porter_add_test(test_kinematics_no_alloc SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_kinematics_no_alloc.cpp
  LIBS porter::core porter::core_io)
porter_add_test(test_robot_loader SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_robot_loader.cpp
  LIBS porter::core porter::core_io)
porter_add_test(test_payload SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_payload.cpp
  LIBS porter::core porter::core_io assimp::assimp)
porter_add_test(test_mesh_hostile SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_mesh_hostile.cpp
  LIBS porter::core porter::core_io)
