#pragma once
// A trace of a validated trajectory for pictures (scripts/bench draws it): the scene's
// obstacles, the base path and the payload's triangles in W at poses spaced along the motion,
// whose union shows the payload's swept volume.
//
// JSON layout ("format": "porter-validate-trace/1"):
//   {"scene": name, "bounds": {"min": [x,y,z], "max": [x,y,z]},
//    "obstacles": [{"name", "kind": "box"|"cylinder"|"sphere"|"mesh", "T_W_shape": 4x4 rows,
//                   "size": [sx,sy,sz] | "radius", "length" | "radius" | "bounds_min", "bounds_max"}],
//    "base": [[t_s, x_m, y_m, yaw_rad], ...],
//    "payload": [{"t_s", "triangles": [[[x,y,z] x3], ...]}, ...]}
// Thread-safety: reentrant.

#include <string>

#include "porter/core/payload.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/validation/flat_trajectory.hpp"

namespace porter::validation {

/// payload_spacing_m: least motion of the payload's bounding centre between traced poses.
std::string swept_trace_json(const RobotModel& model, const Payload& payload, const Scene& scene,
                             const FlatTrajectory& trajectory, double payload_spacing_m = 0.05);

}  // namespace porter::validation
