# Tests of the 'scene' concept.
porter_add_test(test_occupancy_grid SOURCES ${CMAKE_CURRENT_LIST_DIR}/test_occupancy_grid.cpp
  LIBS porter::core)
porter_add_test(test_scene
  SOURCES
    ${CMAKE_CURRENT_LIST_DIR}/test_scene_loader.cpp
    ${CMAKE_CURRENT_LIST_DIR}/test_scene_hostile.cpp
    ${CMAKE_CURRENT_LIST_DIR}/test_scene_shipped.cpp
    ${CMAKE_CURRENT_LIST_DIR}/test_scene_voxelizer.cpp
    ${CMAKE_CURRENT_LIST_DIR}/test_scene_ray_cast.cpp
  LIBS porter::core porter::core_io)
