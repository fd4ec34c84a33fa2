#pragma once
// The back-end safety penalty (paper eq. safety_penalty) on KC-SVSDF distances:
//   J_s = w * sum_i sum_j L(max(0, s_thr - d_j(x_i))),  L(x) = x^3,
// (s_thr = ground_margin_m for ground points)
// over obstacle points x_i (obstacle_points.hpp) and links j = 0..7, d_j = D[j] of Algorithm 1
// (kc_svsdf.hpp). With kinematic_filter = false this is the paper's ablation baseline
// svsdf_per_link (each link's SVSDF independently); planner/baselines wraps it under that name.
//
// Prefilter (paper: AABB test around the trajectory): prepare() keeps the obstacle points within
// crop_margin_m of the warm start's per-link swept AABBs; every evaluate() then asks, per point, only
// for the links j that can come within s_thr of it (elsewhere d_j > s_thr, so the penalty and its
// gradient are zero) and skips points with no such link. Two levels: the link's world AABB swept over
// a piece, inflated by s_thr + the field's error bound, must contain the point; then, at that piece's
// samples, the point's distance to the link's own bounding box (link frame) must be within
// s_thr + err + max_step (the most a link point moves between samples). The points are indexed
// in a uniform grid (kCell_m), so each swept box visits only the points near it. Gradients: dJ_s/d(trajectory) = -3 w x^2 dD_j/d(trajectory), D_j's gradient from
// kc_svsdf.hpp (t* held fixed, earlier durations shifted).
//
// Thread-safety: one instance per solve (workspaces inside); evaluate() runs `threads` threads
// internally over the shared, read-only swept body and SDF.

#include <memory>
#include <vector>

#include "porter/backend/kc_svsdf.hpp"
#include "porter/backend/obstacle_points.hpp"
#include "porter/backend/robot_sdf.hpp"
#include "porter/backend/safety_term.hpp"
#include "porter/backend/swept_body.hpp"

namespace porter::backend {

struct SvsdfSafetySettings {
  /// s_thr, m: obstacle points closer than this to a link's swept volume are penalized. > 0. It
  /// must cover what the final kernel re-check adds: the points are voxel centres (half-diagonal
  /// 4.3 cm at 5 cm voxels) and the kernels flag a link within (3 sqrt(3)/2) h = 13 cm of an
  /// occupied voxel's box in the worst case (robot_kernels.hpp), plus the field's error (<= 1 cm).
  /// 0.15 m passes the re-check in practice; below ~0.1 m it mostly does not. Must stay below the
  /// SDF's fine padding (0.25 m).
  double safety_margin_m = 0.15;
  /// The margin against ground points (voxel centres at z = -res/2), m (0 < ground_margin_m <=
  /// safety_margin_m). The ground lies under the whole trajectory and the scenes' carry pose holds
  /// the T's crossbar 9 cm above it (11.5 cm from the ground points), which the kernel check
  /// accepts: the obstacle margin there would fight every configuration the front-end chose.
  double ground_margin_m = 0.125;
  /// w: cost per m^3 of violation. > 0.
  double weight = 1e5;
  /// Obstacle points are kept within this distance of the warm start's swept AABBs, m (>= s_thr);
  /// the trajectory may move that far during the solve.
  double crop_margin_m = 0.5;
  ObstaclePointSettings points;
  KcSvsdfSettings kc;
  SweptBodySettings body;
  /// Threads sharing the obstacle points of one evaluate() (point i goes to thread i mod threads;
  /// results are merged in thread order, so they do not depend on timing). >= 1; 1 = no thread.
  int threads = 2;
};

class SvsdfSafetyTerm : public SafetyTerm {
 public:
  /// `model` and `sdf` must outlive the term (the SDF belongs to the model with its payload).
  SvsdfSafetyTerm(const RobotModel& model, const RobotSdf& sdf, const SvsdfSafetySettings& settings);

  void prepare(const OccupancyGrid& map_W, const Trajectory& initial) override;
  double evaluate(const Trajectory& trajectory, TrajectoryGradient& grad, SafetyStats* stats) override;
  std::string name() const override { return settings_.kc.kinematic_filter ? "kc_svsdf" : "svsdf_per_link"; }

  const SvsdfSafetySettings& settings() const { return settings_; }
  /// Replaces the obstacle points (constructed test cases; prepare() overwrites them).
  void set_points(std::vector<ObstaclePoint> points) {
    points_ = std::move(points);
    index_points();
  }
  const std::vector<ObstaclePoint>& points() const { return points_; }
  /// Work counters accumulated over every evaluate() since construction (or reset_stats()).
  KcSvsdfStats kc_stats() const;
  SvsdfStats svsdf_stats() const;
  void reset_stats();
  /// The swept body of the last evaluate().
  const SweptBody& body() const { return body_; }

 private:
  struct Worker {
    Worker(const RobotSdf& sdf, const SweptBody& body, const KcSvsdfSettings& settings)
        : kc(sdf, body, settings) {}
    KcSvsdf kc;
    KcSvsdfResult result;
    TrajectoryGradient grad;
    SafetyStats stats;
    double cost = 0.0;
  };
  /// Cell edge of the point index, m (about a link's swept box per piece).
  static constexpr double kCell_m = 0.25;
  void index_points();
  Eigen::Vector3i cell_index(const Eigen::Vector3d& p) const;
  /// The prefilter (header comment): masks_[i] = links point i must be evaluated for.
  void find_candidates();
  void run(Worker& worker, int index, const Trajectory& trajectory);

  const RobotSdf* sdf_;
  SvsdfSafetySettings settings_;
  SweptBody body_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::vector<ObstaclePoint> points_;
  Eigen::AlignedBox3d grid_box_;
  Eigen::Vector3i grid_dims_ = Eigen::Vector3i::Ones();
  std::vector<int> cell_start_;    ///< CSR offsets, one per cell + 1
  std::vector<int> cell_points_;   ///< point indices, cell by cell
  std::vector<std::uint32_t> masks_;
  std::vector<int> candidates_;
};

}  // namespace porter::backend
