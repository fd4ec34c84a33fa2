# Sources of the 'scene' concept (see CMakeLists.txt beside this file).
# The math (scene struct, occupancy grid, voxelizer, ray casting, random generators) is in
# porter_core; the YAML loader is in porter_core_io.
target_sources(porter_core PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/occupancy_grid.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/scene.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/scene_random.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/scene_ray_cast.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/scene_voxelizer.cpp)
target_sources(porter_core_io PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src/scene_loader.cpp)
