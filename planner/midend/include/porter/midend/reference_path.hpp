#pragma once
// The front-end path as the mid-end uses it: cleaned, regrouped into gear segments and densified
// so that every MINCO piece joins two consecutive reference nodes.
//
// From a WholeBodyPath (planner/common/.../whole_body_path.hpp), build_reference_path():
//   1. rejects empty paths, non-finite values and eta not in {+1, -1};
//   2. joins segments: when segment i+1 does not start at segment i's last node it is prefixed
//      with that node (the gear switch happens where the previous segment ended);
//   3. drops consecutive coincident nodes (base position and every joint within
//      coincident_tolerance);
//   4. removes segments whose base path is shorter than min_segment_length_m ("zero-length"
//      segments: the base does not move, so there is no gear switch); their arm motion is kept
//      by appending their nodes to the previous segment (or prepending to the next one);
//   5. merges consecutive segments with the same eta;
//   6. splits every edge longer than densify_factor * rho_b (base metric
//      sqrt(|dp|^2 + w_phi dyaw^2)) or densify_factor * rho_m (joints) into equal sub-edges with
//      linearly interpolated nodes (yaw along the shortest arc);
//   7. allocates initial durations from a speed profile over all pieces: node speeds bounded by
//      the wheel speed on the edge's curvature (v (1 + d_w |kappa| / 2) <= r omega_max), the
//      joint speeds, 0 at the global start and goal, v_ns at gear switches, then forward/backward
//      passes with the wheel acceleration bound (a <= r alpha_max), all at
//      initial_speed_fraction of the limits; a piece lasts 2 L / (v_k + v_k+1), at least its
//      heading / joint motion at the limited rates and min_initial_piece_duration_s. The
//      front-end's node times are not used (they are a plan's guess, often a cruise speed far
//      below the limits).
// Pure function; thread-safe.

#include <string>
#include <vector>

#include "porter/core/types.hpp"
#include "porter/midend/midend_limits.hpp"
#include "porter/midend/midend_settings.hpp"
#include "porter/planner/whole_body_path.hpp"

namespace porter::midend {

struct ReferenceSegment {
  int eta = 1;
  std::vector<RobotConfiguration> nodes;  ///< >= 2; piece i joins nodes[i] and nodes[i+1]
  std::vector<double> durations_s;        ///< initial guess, one per piece
  int num_pieces() const { return static_cast<int>(durations_s.size()); }
};

struct ReferencePath {
  std::vector<ReferenceSegment> segments;  ///< consecutive segments have opposite eta
  int num_pieces() const {
    int n = 0;
    for (const auto& s : segments) n += s.num_pieces();
    return n;
  }
};

enum class ReferenceOutcome {
  kOk,
  kEmpty,       ///< no node at all
  kMalformed,   ///< non-finite value or bad eta; message says where
  kNoMotion,    ///< every node coincides (path reduces to a single configuration)
};

struct ReferenceBuild {
  ReferenceOutcome outcome = ReferenceOutcome::kEmpty;
  std::string message;
  ReferencePath path;                    ///< valid for kOk
  RobotConfiguration single;             ///< the configuration, for kNoMotion
};

ReferenceBuild build_reference_path(const planner::WholeBodyPath& path, const MidendLimits& limits,
                                    const MidendSettings& settings);

}  // namespace porter::midend
