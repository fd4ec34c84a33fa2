#pragma once
// Self-collision of the planning links (base + mast, arm links, gripper + payload).
//
// Definition (what is conservative with respect to what): the configuration is in
// self-collision when, for some pair of links (a, b) that the model's AllowedCollisionMatrix
// does not allow, the exact closed geometries of a and b intersect. (The voxel-level alternative,
// "both touch a common world voxel", is useless here: the Piper's wrist links 4/6 and 5/7 are
// always within 6-11 mm of each other, so they share voxels in almost every pose.)
// Pairs that overlap by construction must be allowed by the robot config (allowed_collisions):
// for the Piper, links 2/4 and 3/5 overlap in every configuration (joints 4 and 5 share an
// origin), and a model that does not allow them is in self-collision everywhere.
//
// How it is checked, per pair, without any joint sampling:
//   1. Build-time proof: when the relative pose of a and b depends on at most two joints (the
//      joints a+1..min(b, 6)), a branch-and-bound over those joints' ranges tries to prove that
//      the pair can never touch: for a joint box it runs, at the box centre, an adaptive octree
//      (distance-grid lower bounds first, exact signed distances of both links where those do
//      not decide) showing that no point of b comes within M of a, where M bounds how far a
//      point of b moves relative to a inside the box: sum over the box's joints of the
//      half-width times the point's distance from the joint's origin plus twice the global bound
//      (half-widths times chain radii). Proven pairs are never checked at run time. A pair whose
//      proof needs more than proof_max_boxes joint boxes, or that touches, stays checked.
//   2. Run time, every other pair: of the two links, b is the one of smaller volume and a the
//      other. The centres of the voxels (edge s, link frame of b) that b's geometry meets (solid,
//      exact rasterization), in an eight-wide sphere tree, are moved into a's frame; a subtree is skipped when
//      a's distance grid (link_distance.hpp, a lower bound) proves its sphere farther than
//      s sqrt(3)/2 from a; a remaining point hits when its exact distance to a's shapes is at
//      most s sqrt(3)/2. Any point x common to a and b lies in one of those voxels, whose centre
//      is within s sqrt(3)/2 of x and hence of a: no overlap is missed.
//      Order of the run-time tests: the links' bounding spheres, eight pairs per test; then the
//      root spheres of the sample trees of the pairs left, eight pairs of one grid link per test,
//      against the boxes around a's shapes (BoxUnionBound), then a's grid for the spheres left
//      (unless larger than the grid's cap); then the trees below the roots, pair by pair in check
//      order, a node's child spheres that the grid leaves open tried against the boxes too.
//      Why the boxes first: they read no memory, and they clear more root spheres than the grid,
//      whose bound outside its box is only the distance to that box (the payload's large root
//      sphere next to the base is the common case).
//      A reported pair is at most s sqrt(3) + 0.1 mm apart (inflation_bound_m(); the 0.1 mm
//      covers float32 rounding of poses and points).
//
// Frames: link frames in the base frame B (ArmPoses::T_B_L). Units: metres.
// Thread-safety: immutable after construction; concurrent check() calls are safe.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/collision/kernel_kinematics.hpp"
#include "porter/planner/collision/link_distance.hpp"
#include "porter/planner/collision/wide_point_tree.hpp"

namespace porter::planner {

struct SelfCollisionSettings {
  /// Voxel edge s of the link rasters: run-time samples and distance grids (m). Inflation bound
  /// s sqrt(3).
  double sample_spacing_m = 0.01;
  /// Try the build-time proofs (pairs moved by at most two joints).
  bool prove_pairs = true;
  /// Joint boxes examined per pair before giving up on a proof.
  int proof_max_boxes = 3000;
  /// Smallest octree cell half-size of a proof (m); a pair closer than about this is not proven.
  double proof_min_cell_m = 0.0005;
};

enum class PairStatus {
  kAllowed,     ///< allowed by the model: never checked
  kProvenFree,  ///< proven at build time never to touch: never checked
  kChecked,     ///< checked at run time
};

class SelfCollisionChecker {
 public:
  SelfCollisionChecker(const RobotModel& model, const SelfCollisionSettings& settings);

  /// First non-allowed pair found touching: link = a, other_link = b (a < b).
  CollisionResult check(const ArmPoses& poses) const;
  /// check() of the configurations in the lanes of `poses` whose bit is set in `lanes`: results[i]
  /// for lane i, the others untouched. The bounding-sphere and root-sphere tests run for eight
  /// configurations at a time (one per lane), the tree walks per configuration.
  void check_lanes(const ArmPoseLanes& poses, std::uint32_t lanes, CollisionResult* results) const;

  PairStatus pair_status(int a, int b) const {
    return status_[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)];
  }
  int num_checked_pairs() const { return static_cast<int>(pairs_.size()); }
  /// The pairs checked at run time (status kChecked) as {a, b}, a < b, in link order.
  std::vector<std::array<int, 2>> checked_pairs() const {
    std::vector<std::array<int, 2>> out;
    for (int a = 0; a < kNumLinks; ++a)
      for (int b = a + 1; b < kNumLinks; ++b)
        if (pair_status(a, b) == PairStatus::kChecked) out.push_back({a, b});
    return out;
  }
  double inflation_bound_m() const { return 2.0 * static_cast<double>(threshold_m_); }
  /// Signed distance to link `link`'s exact geometry (link frame), as used by the check.
  const LinkDistance& link_distance(int link) const { return links_[static_cast<std::size_t>(link)]; }
  std::size_t bytes() const;

 private:
  bool prove_separated(const RobotModel& model, int a, int b) const;
  /// Pair p (index into pairs_) touches, given b's frame in a's frame: the walk below the root.
  bool pair_hit(std::size_t p, const Pose4f& T_a_b) const;
  CollisionResult pair_result(std::size_t p) const;

  SelfCollisionSettings settings_;
  std::array<LinkDistance, kNumLinks> links_;
  std::array<DistanceGrid, kNumLinks> grids_;
  std::array<BoxUnionBound, kNumLinks> boxes_;  ///< far-field bounds of the grid links (root tests)
  std::array<Eigen::Vector3f, kNumLinks> sphere_centre_{};  ///< link bounding spheres (link frame)
  std::array<float, kNumLinks> sphere_radius_{};
  WidePointTreePool samples_;  ///< tree k = samples of link k (link frame)
  std::array<std::array<PairStatus, kNumLinks>, kNumLinks> status_{};
  std::vector<std::array<int, 2>> pairs_;  ///< checked pairs {grid link, sampled link}, in check order
  /// The checked pairs eight at a time, for the bounding-sphere test of check(): lane i of chunk
  /// c is pair 8c + i (grid link a, sampled link b, squared sum of the sphere radii + threshold;
  /// spare lanes have reach2 -1 and never pass).
  struct alignas(32) PairLanes {
    std::int32_t a[8], b[8];
    float reach2[8];
  };
  std::vector<PairLanes> pair_lanes_;
  /// The checked pairs grouped by grid link, eight per group, for the root-sphere test of
  /// check(): lane i is pair pair[i] (sampled link b[i], root radius + threshold need[i]); spare
  /// lanes have lane_bits clear.
  struct alignas(32) RootGroup {
    std::int32_t b[8];
    float need[8];
    std::int32_t pair[8];
    int a = 0;
    std::uint32_t lane_bits = 0;  ///< used lanes
    std::uint32_t pair_bits = 0;  ///< bit p for every pair p of the group
  };
  std::vector<RootGroup> root_groups_;
  /// Links whose sample trees some pair uses.
  std::vector<int> sampled_links_;
  float threshold_m_ = 0.f;
  ChainRadii radii_;
};

}  // namespace porter::planner
