#pragma once
// Multilayer constrained RRT*-Connect for the arm (paper §IV-A, after REMANI).
//
// The base path is fixed: layer i is base waypoint i. A node is (layer, q). Two trees grow, one
// from (0, q_start) toward higher layers and one from (N-1, q_goal) toward lower layers. A
// sample picks a layer (from the part of the problem the tree can reach, biased toward its
// frontier) and a q within the joint limits; the tree extends from its nearest node in the
// adjacent layer by at most arm_speed_fraction * qdot_max_j * dt_i per joint j, so an edge
// between layers i and i+1 always respects the joint speed limits over the time dt_i the base
// needs between the two waypoints. A node is valid when the whole body at (base_i, q) is
// collision-free; an edge when CollisionChecker::check_motion between the two whole-body
// configurations is (the base moves along the chord between the waypoints). RRT*: a new node
// takes the cheapest valid parent in the previous layer and rewires the next layer, on the
// joint-motion cost sum_j |dq_j| (from the first connection on, see
// optimize_before_connection). After every new node the tree tries to connect to the other
// tree's nodes in the adjacent layer. Samples: uniform (layer, q); local steps that re-draw one
// or two joints of an existing node (narrow passages usually need a few joints to change while
// the others hold); and greedy chains (RRT-Connect's connect step) that extend a node layer by
// layer toward the other tree's frontier configuration or holding its own configuration.
// Narrow passages: the layers where neither the start's nor the goal's arm configuration fits
// form "blocked stretches"; corridor steps draw configurations until one fits a whole stretch
// (cheap node checks with early exit, then the held motion through it), and both trees then
// chain toward it from a few layers outside the stretch, so the arm reshapes in the open and
// holds the shape through the passage, where the two trees meet.
//
// Stops refine_iterations after the first connection (so results do not depend on machine
// speed), at max_iterations, or at the time budget; a successful solution is then shortened by
// shortcut_attempts random shortcuts (straight joint-space lines across several layers). Deterministic for a given seed when it
// ends before the budget.
//
// Thread-safety: plan() is const and reentrant; the checker must not change its map meanwhile.

#include <cstdint>
#include <vector>

#include "porter/core/robot_model.hpp"
#include "porter/frontend/stage_report.hpp"
#include "porter/planner/collision/collision_checker.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::frontend {

struct LayeredArmSettings {
  /// Fraction of each joint's velocity limit an edge may use over its layer time (0 .. 1].
  double arm_speed_fraction = 0.8;
  /// Probability of a greedy chain (RRT-Connect's connect step) [0, 1].
  double goal_bias = 0.45;
  /// Share of those chains that hold the starting node's configuration instead of heading for
  /// the other tree's frontier [0, 1].
  double hold_bias = 0.5;
  /// Probability of a local step: a node's configuration with one or two joints re-drawn
  /// (goal_bias + local_bias <= 1; the rest are uniform samples). With the defaults, 0.45 / 0.4
  /// and corridor_bias 0.15, uniform samples are drawn only when there is no blocked stretch:
  /// they helped least (bridge h_b = 0.8 m, 100 seeds, p97 front-end time 120 -> 60 ms when the
  /// uniform share went from 0.15 to 0).
  double local_bias = 0.4;
  /// Probability of a corridor step when there are blocked stretches (layers where neither the
  /// start's nor the goal's arm configuration fits): it draws configurations until one fits the
  /// whole stretch (while fewer than max_corridor_targets are known) and chains a tree toward a
  /// known one from outside the stretch (goal_bias + local_bias + corridor_bias <= 1).
  double corridor_bias = 0.15;
  /// Configurations drawn per corridor step (>= 1); one that fits every layer of the stretch
  /// and the held motion through it becomes a corridor configuration.
  int corridor_draws = 200;
  /// Base travel on each side of a stretch over which a corridor configuration must fit as well
  /// (m, >= 0): the payload reaches past the base, so the shape has to be held longer (the
  /// layers within this distance of the stretch along the base path are added). Measured on
  /// bridge, 100 seeds, 3 s budget, p97 of the front-end time at h_b = 0.8 / 0.9 m (goal_bias
  /// 0.45, local_bias 0.4): 0.75 m 60 / 39 ms, 1 m 40 / 33 ms, 1.5 m 14 / 9 ms, 2 m 11 / 8 ms;
  /// at 2 m the forest's success within 200 ms fell from 97 to 93 % (wider stretches, fewer
  /// shapes fit).
  double corridor_margin_m = 1.5;
  /// Corridor configurations kept per stretch (>= 0; 0 disables corridor steps).
  int max_corridor_targets = 4;
  /// Share of greedy chains that head for a corridor configuration of the next stretch ahead,
  /// when one is known [0, 1].
  double corridor_target_bias = 0.5;
  /// A greedy-chain step that fails moving all joints is retried this often moving a random
  /// subset of the joints toward the target (>= 0).
  int chain_retries = 2;
  /// Probability that a random sample's layer is drawn near the tree's frontier [0, 1].
  double frontier_bias = 0.5;
  /// Width of that frontier window, layers (>= 1).
  int frontier_window = 4;
  /// Run RRT* choose-parent and rewiring from the start. When false (default) they start with
  /// the first connection; before it a new node hangs from the node it grew from, which costs
  /// one edge check instead of several and finds the first path faster.
  bool optimize_before_connection = false;
  /// Parent candidates whose edges are checked for one new node (RRT* choose-parent, >= 1).
  int max_parent_candidates = 4;
  /// Candidates in the other tree checked per connection attempt (>= 1).
  int max_connect_candidates = 3;
  /// Iterations spent improving after the first connection (>= 0).
  int refine_iterations = 30;
  /// Shortcut attempts on the solution (>= 0): a random pair of layers i < j (at most
  /// shortcut_max_layers apart) whose arm configurations are joined by the straight line in
  /// joint space, spread evenly over the layers between, replaces the stretch when every node
  /// and edge is collision-free, every step within the per-layer joint speed limit and the
  /// joint motion shorter. The trees' solution zig-zags (random samples). Measured (front-end
  /// probe, mean total arm motion sum_j |dq_j|): bridge h_b = 0.9, 50 seeds 9.8 -> 8.0 rad;
  /// forest, 30 seeds 47.7 -> 38.8 rad; front-end times unchanged within noise. Unlimited spans
  /// (60 attempts) only reached 45.2 rad on the forest: long shortcuts rarely survive there.
  int shortcut_attempts = 200;
  /// Longest shortcut, layers (>= 2; see shortcut_attempts).
  int shortcut_max_layers = 8;
  /// Iteration cap (>= 1). When the trees have not connected by then, the front-end hands the
  /// gap to the whole-body RRT*, which can also move the base off the Hybrid A* path.
  std::int64_t max_iterations = 200000;
};

bool validate_settings(const LayeredArmSettings& s, std::string* why);

struct ArmLayerProblem {
  std::vector<BasePose> bases;  ///< N >= 2 base waypoints (layers), world frame
  std::vector<double> dt_s;     ///< N-1 times between consecutive layers, s (> 0)
  JointVector q_start = JointVector::Zero();  ///< arm at layer 0
  JointVector q_goal = JointVector::Zero();   ///< arm at layer N-1
};

struct LayeredArmResult {
  StageReport report;
  /// Success: the arm configuration at every layer (size N).
  std::vector<JointVector> q;
  double cost = 0.0;  ///< sum over edges of sum_j |dq_j|, rad
  /// Always filled: the forward tree's path to its deepest layer (q for layers
  /// 0..forward_q.size()-1) and the backward tree's path from its shallowest layer (q for
  /// layers N-backward_q.size()..N-1). The whole-body fallback bridges the gap between them.
  std::vector<JointVector> forward_q;
  std::vector<JointVector> backward_q;
};

class LayeredArmPlanner {
 public:
  LayeredArmPlanner(const RobotModel& model, const planner::CollisionChecker& checker,
                    LayeredArmSettings settings = {});
  const LayeredArmSettings& settings() const { return settings_; }

  /// Searches until `deadline` expires (time up: kTimeout; canceled: kCanceled).
  LayeredArmResult plan(const ArmLayerProblem& problem, const planner::Deadline& deadline, std::uint64_t seed) const;
  LayeredArmResult plan(const ArmLayerProblem& problem, double budget_s, std::uint64_t seed) const {
    return plan(problem, planner::Deadline(budget_s), seed);
  }

 private:
  const RobotModel& model_;
  const planner::CollisionChecker& checker_;
  LayeredArmSettings settings_;
};

}  // namespace porter::frontend
