#pragma once
// Internal: the search state of the multilayer constrained RRT*-Connect (layered_arm_planner.hpp
// describes the algorithm). Tree operations are in layered_arm_search.cpp, the sampling
// strategies (greedy chains, local steps, corridor configurations) in layered_arm_sampling.cpp.
// One object per plan() call; not thread-safe.

#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "porter/planner/deadline.hpp"
#include "porter/frontend/layered_arm_planner.hpp"

namespace porter::frontend::detail {

struct ArmNode {
  int layer = 0;
  int tree = 0;  // 0: grown from the start (toward higher layers), 1: from the goal
  JointVector q;
  int parent = -1;
  double cost = 0.0;  // joint motion from the tree's root, rad
  std::vector<int> children;
};

inline double motion_cost(const JointVector& a, const JointVector& b) { return (b - a).cwiseAbs().sum(); }

class LayeredArmSearch {
 public:
  LayeredArmSearch(const RobotModel& model, const planner::CollisionChecker& checker, const LayeredArmSettings& s,
                   const ArmLayerProblem& p, std::uint64_t seed, StageReport& rep);

  planner::Status run(const planner::Deadline& deadline, LayeredArmResult& out);

 private:
  /// A run of layers where neither the start's nor the goal's arm configuration fits.
  struct Stretch {
    int first = 0, last = 0;           // layers
    int lo = 0, hi = 0;                // layers a corridor configuration must fit (margin added)
    std::vector<JointVector> targets;  // configurations free through the whole stretch
  };

  RobotConfiguration config(int layer, const JointVector& q) const;
  bool node_free(int layer, const JointVector& q);
  bool edge_free(int la, const JointVector& qa, int lb, const JointVector& qb);
  bool reachable(int la, const JointVector& qa, int lb, const JointVector& qb) const;
  int add_node(int tree, int layer, const JointVector& q, int parent, double cost);
  void reparent(int child, int new_parent, double new_cost);
  JointVector sample_q();
  int sample_layer(int tree);
  /// Grows `tree` into `layer` toward q_target from `from` (or the nearest node of the previous
  /// layer when from < 0). Returns the new node or -1.
  int extend(int tree, int layer, const JointVector& q_target, int from);
  /// Tries to join node `id` to the other tree's nodes in the adjacent layer.
  bool try_connect(int id);
  int random_node_in(const std::vector<int>& ids);
  /// RRT-Connect style: chains a node near the tree's frontier toward chain_target().
  void greedy_chain(int tree);
  /// Heads for a corridor configuration of the next blocked stretch ahead (corridor_target_bias,
  /// when one is known), holds the node's configuration (hold_bias) or heads for a node of the
  /// other tree a few layers ahead.
  JointVector chain_target(int tree, int node);
  /// Extends layer after layer from `node` toward `target` until a step fails or connects. A
  /// step that fails moving every joint is retried (chain_retries times) moving a random subset
  /// of the joints only: big payloads often need the joints to move in some order.
  void chain(int tree, int node, const JointVector& target);
  /// After a new node that reached the tree's frontier: keep going (extend-then-connect).
  void continue_chain(int tree, int node);
  /// Extends a random node of a layer into the next one with one or two of its joints
  /// re-drawn uniformly within the limits (the others kept): narrow passages usually need a
  /// few joints to change while the rest hold.
  void local_step(int tree);
  /// Runs of layers where neither the start's nor the goal's arm configuration fits: the
  /// narrow passages that need the arm to change.
  void find_stretches();
  /// Finds corridor configurations for a blocked stretch and chains a tree toward one from
  /// outside the stretch (layered_arm_sampling.cpp). False when there is no stretch.
  bool corridor_step();
  std::vector<JointVector> path_to_root(int id) const;
  int cheapest_in_layer(int tree, int layer) const;
  void extract_frontiers(LayeredArmResult& out) const;
  void extract_solution(LayeredArmResult& out) const;
  /// shortcut_attempts random shortcuts on out.q (header comment of layered_arm_planner.hpp);
  /// stops early at the deadline. Updates out.cost.
  void shortcut(const planner::Deadline& deadline, LayeredArmResult& out);
  int next_layer(int tree, int layer) const { return tree == 0 ? layer + 1 : layer - 1; }

  const planner::CollisionChecker& checker_;
  const LayeredArmSettings& s_;
  const ArmLayerProblem& p_;
  int n_;
  std::mt19937_64 rng_;
  StageReport& rep_;
  JointVector lower_, upper_;
  std::vector<JointVector> steps_;  // per layer pair: largest joint change (rad)
  std::vector<ArmNode> nodes_;
  std::vector<std::vector<int>> layers_[2];  // node ids per tree and layer
  int frontier_[2] = {0, -1};                // deepest layer of the start tree, shallowest of the goal tree
  std::vector<Stretch> stretches_;
  std::vector<std::pair<int, int>> connections_;  // (start-tree node, goal-tree node)
};

}  // namespace porter::frontend::detail
