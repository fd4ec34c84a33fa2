#pragma once
// JSON form of a Trajectory (trajectory.hpp), used by the planner CLI's result file, test
// fixtures and offline tools. Part of porter_core_io; the JSON library stays private, so the
// functions trade std::string.
//
// Layout (one object; keys exactly these, no others):
//   {
//     "dimension": 8,              // kTrajDim: z = [p_x, p_y, q1..q6]
//     "degree": 5,                 // kTrajDegree
//     "start_yaw_rad": 0.0,        // heading held while the base has never moved, rad, in W
//     "pieces": [                  // >= 1, in time order
//       { "duration_s": 1.5,       // T_i > 0
//         "eta": 1,                // integer, +1 forward / -1 reverse
//         "coeffs": [[...8...],    // 6 rows: row k multiplies tau^k (tau local to the piece, s);
//                    ...          //   column d is z_d (m/s^k for d = 0, 1; rad/s^k for d >= 2)
//                    [...8...]] }
//     ]
//   }
// Numbers are written with enough digits to read back bit-identical.
//
// Thread-safety: reentrant. Failure: trajectory_from_json returns a TrajectoryResult whose error
// names the key ("pieces[2].coeffs[5]: expected an array of 8 numbers") — a caller reading a file
// turns it into a LoadError naming the file. to_json cannot fail.

#include <string>

#include "porter/core/trajectory.hpp"

namespace porter {

/// The trajectory as a JSON document; indent < 0 writes it on one line, otherwise pretty-printed
/// with that many spaces per level.
std::string to_json(const Trajectory& trajectory, int indent = -1);

/// Parses and validates a document in the layout above (including Trajectory::create's checks).
TrajectoryResult trajectory_from_json(const std::string& text);

}  // namespace porter
