# Robot model: kinematics (porter_core) and its loaders (porter_core_io).
target_sources(porter_core PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/robot_model.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/kinematics.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/payload.cpp)
target_sources(porter_core_io PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/src/yaml_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/mesh_loader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/ply_header.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/text_mesh_counts.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/robot_loader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/src/payload_loader.cpp)
target_link_libraries(porter_core_io PRIVATE console_bridge::console_bridge)
