#include "porter/msg/trajectory_msg.hpp"

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace porter {
namespace {

constexpr int64_t kCoeffsPerPiece = static_cast<int64_t>(kTrajDim) * kTrajNumCoeffs;

int64_t coeff_index(int64_t piece, int d, int k) {
  return (piece * kTrajDim + d) * kTrajNumCoeffs + k;
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.17g", x);
  return buf;
}

TrajectoryMsgResult failure(std::string error) {
  TrajectoryMsgResult r;
  r.error = std::move(error);
  return r;
}

}  // namespace

minco_trajectory_t to_msg(const Trajectory& trajectory, int64_t start_utime, int64_t plan_id,
                          const std::string& frame_id, const std::string& payload_id) {
  minco_trajectory_t msg;
  msg.utime = start_utime;
  msg.start_utime = start_utime;
  msg.plan_id = plan_id;
  msg.frame_id = frame_id;
  msg.payload_id = payload_id;
  msg.dimension = kTrajDim;
  msg.order = kTrajDegree;
  msg.start_yaw_rad = trajectory.start_yaw_rad();
  const int n = trajectory.num_pieces();
  msg.num_pieces = n;
  msg.durations_s.resize(static_cast<size_t>(n));
  msg.eta.resize(static_cast<size_t>(n));
  msg.num_coeffs = static_cast<int32_t>(n * kCoeffsPerPiece);
  msg.coeffs.resize(static_cast<size_t>(msg.num_coeffs));
  for (int i = 0; i < n; ++i) {
    const TrajectoryPiece& p = trajectory.piece(i);
    msg.durations_s[static_cast<size_t>(i)] = p.duration_s;
    msg.eta[static_cast<size_t>(i)] = static_cast<int8_t>(p.eta);
    for (int d = 0; d < kTrajDim; ++d)
      for (int k = 0; k < kTrajNumCoeffs; ++k)
        msg.coeffs[static_cast<size_t>(coeff_index(i, d, k))] = p.coeffs(k, d);
  }
  return msg;
}

static TrajectoryMsgResult convert(const minco_trajectory_t& msg) {
  if (msg.dimension != kTrajDim) {
    return failure("dimension: expected " + std::to_string(kTrajDim) + " (got " +
                   std::to_string(msg.dimension) + ")");
  }
  if (msg.order != kTrajDegree) {
    return failure("order: expected " + std::to_string(kTrajDegree) + " (got " +
                   std::to_string(msg.order) + ")");
  }
  if (msg.num_pieces < 1) {
    return failure("num_pieces: must be >= 1 (got " + std::to_string(msg.num_pieces) + ")");
  }
  const int64_t n = msg.num_pieces;
  if (static_cast<int64_t>(msg.durations_s.size()) != n) {
    return failure("durations_s: has " + std::to_string(msg.durations_s.size()) +
                   " entries but num_pieces is " + std::to_string(n));
  }
  if (static_cast<int64_t>(msg.eta.size()) != n) {
    return failure("eta: has " + std::to_string(msg.eta.size()) + " entries but num_pieces is " +
                   std::to_string(n));
  }
  if (static_cast<int64_t>(msg.num_coeffs) != n * kCoeffsPerPiece) {
    return failure("num_coeffs: expected num_pieces * dimension * (order + 1) = " +
                   std::to_string(n * kCoeffsPerPiece) + " (got " + std::to_string(msg.num_coeffs) +
                   ")");
  }
  if (static_cast<int64_t>(msg.coeffs.size()) != static_cast<int64_t>(msg.num_coeffs)) {
    return failure("coeffs: has " + std::to_string(msg.coeffs.size()) +
                   " entries but num_coeffs is " + std::to_string(msg.num_coeffs));
  }
  if (!std::isfinite(msg.start_yaw_rad)) {
    return failure("start_yaw_rad: must be finite (got " + num(msg.start_yaw_rad) + ")");
  }

  std::vector<TrajectoryPiece> pieces(static_cast<size_t>(n));
  for (int64_t i = 0; i < n; ++i) {
    TrajectoryPiece& p = pieces[static_cast<size_t>(i)];
    p.duration_s = msg.durations_s[static_cast<size_t>(i)];
    if (!std::isfinite(p.duration_s) || !(p.duration_s > 0.0)) {
      return failure("durations_s[" + std::to_string(i) + "]: must be finite and > 0 (got " +
                     num(p.duration_s) + ")");
    }
    p.eta = msg.eta[static_cast<size_t>(i)];
    if (p.eta != 1 && p.eta != -1) {
      return failure("eta[" + std::to_string(i) + "]: must be +1 or -1 (got " +
                     std::to_string(p.eta) + ")");
    }
    for (int d = 0; d < kTrajDim; ++d) {
      for (int k = 0; k < kTrajNumCoeffs; ++k) {
        const int64_t idx = coeff_index(i, d, k);
        const double c = msg.coeffs[static_cast<size_t>(idx)];
        if (!std::isfinite(c)) {
          return failure("coeffs[" + std::to_string(idx) + "] (piece " + std::to_string(i) +
                         ", d " + std::to_string(d) + ", k " + std::to_string(k) +
                         "): must be finite (got " + num(c) + ")");
        }
        p.coeffs(k, d) = c;
      }
    }
  }
  TrajectoryResult built = Trajectory::create(std::move(pieces), msg.start_yaw_rad);
  if (!built.ok()) return failure(built.error);
  TrajectoryMsgResult r;
  r.value.emplace(StampedTrajectory{std::move(*built.trajectory), msg.utime, msg.start_utime,
                                    msg.plan_id, msg.frame_id, msg.payload_id});
  return r;
}

TrajectoryMsgResult from_msg(const minco_trajectory_t& msg) {
  try {
    return convert(msg);
  } catch (const std::exception& e) {  // std::bad_alloc: the header promises no exception
    return failure(std::string("cannot convert the message: ") + e.what());
  }
}

}  // namespace porter
