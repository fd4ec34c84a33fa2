#pragma once
// Removes LiDAR points on the robot itself: a point is on the robot when it lies within
// margin_m of the collision geometry of any planning link (payload included, it is part of
// link 7) at the measured configuration. Exact up to floating point: a point is removed if and
// only if its signed distance to some link's shapes is <= margin_m.
//
// How: each link's shapes are sampled once, in the link frame, on a grid of cell_m; a cell is
// "inside" when every point of it is within the margin (distance at its centre <= margin - half
// diagonal), "outside" when none is (> margin + half diagonal), otherwise "boundary". A query
// point is tested against the links whose bounding ball (grown by the margin) holds it; only
// points in boundary cells pay for an exact signed-distance test.
//
// Frames: points in the base frame B (the sensor is fixed on the base, so base-link points need
// no motion compensation); the arm's link poses come from set_arm(q).
// Thread-safety: contains() is const; set_arm() needs exclusive access.

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/robot_model.hpp"
#include "porter/core/types.hpp"

namespace porter::mapping {

struct SelfFilterParams {
  double margin_m = 0.05;   ///< inflation of the robot and payload geometry, m (>= 0)
  double cell_m = 0.01;     ///< precomputed grid cell, m (> 0)
};

class SelfFilter {
 public:
  SelfFilter(const RobotModel& robot, const SelfFilterParams& params);

  /// Poses the arm links (base-frame poses from arm forward kinematics).
  void set_arm(const JointVector& q_rad);
  /// True when p_B is within the margin of the robot (at the last set_arm()).
  bool contains(const Eigen::Vector3d& p_B) const;
  /// Exact minimum signed distance from p_B to the robot's geometry, m (slow; for tests).
  double signed_distance(const Eigen::Vector3d& p_B) const;

  const SelfFilterParams& params() const { return params_; }
  /// Cells of all links' grids, and how many are boundary cells.
  std::int64_t cells() const;
  std::int64_t boundary_cells() const;
  std::uint64_t exact_tests() const { return exact_tests_; }

 private:
  enum Cell : std::uint8_t { kOutside = 0, kInside = 1, kBoundary = 2 };
  struct LinkGrid {
    Eigen::Vector3d origin_L = Eigen::Vector3d::Zero();
    Eigen::Vector3i dims = Eigen::Vector3i::Zero();
    std::vector<std::uint8_t> cells;
    Eigen::Vector3d center_L = Eigen::Vector3d::Zero();
    double radius_m = -1.0;  ///< < 0: no geometry
  };
  double link_distance(int link, const Eigen::Vector3d& p_L) const;

  RobotModel robot_;
  SelfFilterParams params_;
  std::array<LinkGrid, kNumLinks> grids_;
  std::array<Eigen::Isometry3d, kNumLinks> T_L_B_;
  std::array<Eigen::Vector3d, kNumLinks> center_B_;
  mutable std::uint64_t exact_tests_ = 0;
};

}  // namespace porter::mapping
