# Tests of the 'geometry' concept.
porter_add_test(test_geometry
  SOURCES
    ${CMAKE_CURRENT_LIST_DIR}/test_geometry.cpp
    ${CMAKE_CURRENT_LIST_DIR}/test_geometry_intersect.cpp
    ${CMAKE_CURRENT_LIST_DIR}/test_geometry_ray.cpp
  LIBS porter::core)
