# Tests of the 'trajectory' concept.
porter_add_test(test_trajectory
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_trajectory.cpp
          ${CMAKE_CURRENT_LIST_DIR}/test_trajectory_base.cpp
  LIBS porter::core)
# Replaces the global operator new to count allocations: its own executable.
porter_add_test(test_trajectory_alloc
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_trajectory_alloc.cpp
  LIBS porter::core)
porter_add_test(test_trajectory_json
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_trajectory_json.cpp
  LIBS porter::core_io)
