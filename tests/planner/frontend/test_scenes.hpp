#pragma once
// Small scenes for the front-end unit tests (YAML text; paths resolve against config/scenes/).

#include <string>

namespace porter::test {

/// 9 x 7 m open floor, T bar, start (0, 0, 0), goal (5, 0, 0), arm folded as in the shipped scenes.
inline std::string open_scene_yaml(const std::string& goal_base = "[5.0, 0.0, 0.0]") {
  return "name: open\n"
         "bounds: {min: [-2.0, -3.5, 0.0], max: [7.0, 3.5, 2.5]}\n"
         "resolution: 0.05\n"
         "start: {base: [0.0, 0.0, 0.0], arm: [0.0, 0.6, -0.9, 0.0, 0.5, 0.0]}\n"
         "goal: {base: " + goal_base + ", arm: [0.0, 0.6, -0.9, 0.0, 0.5, 0.0]}\n"
         "payload: ../payloads/t_bar.yaml\n";
}

/// A wall across the floor at x = 2.5 with one 1.2 m gap (y in [1.1, 2.3]): the base must detour.
inline std::string gap_scene_yaml() {
  return open_scene_yaml() +
         "obstacles:\n"
         "  - box: {name: wall_low, center: [2.5, -1.2, 1.25], size: [0.3, 4.6, 2.5]}\n"
         "  - box: {name: wall_high, center: [2.5, 2.9, 1.25], size: [0.3, 1.2, 2.5]}\n";
}

/// The goal (5, 0) enclosed by four walls: no path exists.
inline std::string walled_goal_scene_yaml() {
  return open_scene_yaml() +
         "obstacles:\n"
         "  - box: {name: n, center: [5.0, 1.5, 1.0], size: [3.3, 0.3, 2.0]}\n"
         "  - box: {name: s, center: [5.0, -1.5, 1.0], size: [3.3, 0.3, 2.0]}\n"
         "  - box: {name: e, center: [6.5, 0.0, 1.0], size: [0.3, 3.3, 2.0]}\n"
         "  - box: {name: w, center: [3.5, 0.0, 1.0], size: [0.3, 3.3, 2.0]}\n";
}

}  // namespace porter::test
