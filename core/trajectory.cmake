# Sources of the 'trajectory' concept (see CMakeLists.txt beside this file).
# The math (evaluation, heading rule, wheel rates) is in porter_core; the JSON form is in
# porter_core_io, which links nlohmann_json privately.
target_sources(porter_core PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src/trajectory.cpp)
target_sources(porter_core_io PRIVATE ${CMAKE_CURRENT_LIST_DIR}/src/trajectory_json.cpp)
