# Sources of the 'geometry' concept (see CMakeLists.txt beside this file).
target_sources(porter_core PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/geometry.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/geometry_aabb.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/geometry_mesh.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/geometry_ray.cpp)
