#include "layered_arm_search.hpp"

#include "tree_rewire.hpp"

#include <algorithm>

namespace porter::frontend::detail {

LayeredArmSearch::LayeredArmSearch(const RobotModel& model, const planner::CollisionChecker& checker,
                                   const LayeredArmSettings& s, const ArmLayerProblem& p, std::uint64_t seed,
                                   StageReport& rep)
    : checker_(checker), s_(s), p_(p), n_(static_cast<int>(p.bases.size())), rng_(seed), rep_(rep),
      lower_(model.lower_limits()), upper_(model.upper_limits()) {
  steps_.resize(static_cast<std::size_t>(std::max(0, n_ - 1)));
  for (int i = 0; i + 1 < n_; ++i)
    steps_[static_cast<std::size_t>(i)] = s.arm_speed_fraction * p.dt_s[static_cast<std::size_t>(i)] * model.velocity_limits();
  layers_[0].resize(static_cast<std::size_t>(n_));
  layers_[1].resize(static_cast<std::size_t>(n_));
}

planner::Status LayeredArmSearch::run(const planner::Deadline& deadline, LayeredArmResult& out) {
  if (!node_free(0, p_.q_start)) return planner::Status::kInvalidStart;
  if (!node_free(n_ - 1, p_.q_goal)) return planner::Status::kInvalidGoal;
  const int root_f = add_node(0, 0, p_.q_start, -1, 0.0);
  add_node(1, n_ - 1, p_.q_goal, -1, 0.0);
  try_connect(root_f);
  if (connections_.empty()) find_stretches();
  std::int64_t first_connection_it = connections_.empty() ? -1 : 0;
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  planner::Status status = planner::Status::kNoPath;
  while (true) {
    if (!connections_.empty()) {
      if (first_connection_it < 0) first_connection_it = rep_.iterations;
      if (rep_.iterations - first_connection_it >= s_.refine_iterations) break;
    }
    if (n_ <= 2) break;
    if (rep_.iterations >= s_.max_iterations || deadline.expired()) {
      status = planner::Status::kTimeout;
      break;
    }
    ++rep_.iterations;
    const int t = static_cast<int>(rep_.iterations % 2);
    const double u = u01(rng_);
    if (u < s_.goal_bias) {
      greedy_chain(t);
    } else if (u < s_.goal_bias + s_.local_bias) {
      local_step(t);
    } else if (u < s_.goal_bias + s_.local_bias + s_.corridor_bias && corridor_step()) {
      // searched for a corridor configuration
    } else {
      const int l = sample_layer(t);
      const int id = extend(t, l, sample_q(), -1);
      if (id >= 0 && !try_connect(id)) continue_chain(t, id);
    }
  }
  extract_frontiers(out);
  if (connections_.empty()) return status;
  extract_solution(out);
  shortcut(deadline, out);
  return planner::Status::kSuccess;
}

RobotConfiguration LayeredArmSearch::config(int layer, const JointVector& q) const {
  return RobotConfiguration{p_.bases[static_cast<std::size_t>(layer)], q};
}

bool LayeredArmSearch::node_free(int layer, const JointVector& q) {
  ++rep_.collision_checks;
  return !checker_.check(config(layer, q));
}

bool LayeredArmSearch::edge_free(int la, const JointVector& qa, int lb, const JointVector& qb) {
  ++rep_.collision_checks;
  if (la > lb) return !checker_.check_motion(config(lb, qb), config(la, qa));
  return !checker_.check_motion(config(la, qa), config(lb, qb));
}

bool LayeredArmSearch::reachable(int la, const JointVector& qa, int lb, const JointVector& qb) const {
  const JointVector& step = steps_[static_cast<std::size_t>(std::min(la, lb))];
  return ((qb - qa).cwiseAbs().array() <= step.array() * (1.0 + 1e-9)).all();
}

int LayeredArmSearch::add_node(int tree, int layer, const JointVector& q, int parent, double cost) {
  ArmNode n;
  n.layer = layer;
  n.tree = tree;
  n.q = q;
  n.parent = parent;
  n.cost = cost;
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back(std::move(n));
  if (parent >= 0) nodes_[static_cast<std::size_t>(parent)].children.push_back(id);
  layers_[tree][static_cast<std::size_t>(layer)].push_back(id);
  if (tree == 0) frontier_[0] = std::max(frontier_[0], layer);
  else frontier_[1] = frontier_[1] < 0 ? layer : std::min(frontier_[1], layer);
  return id;
}

void LayeredArmSearch::reparent(int child, int new_parent, double new_cost) {
  reparent_subtree(nodes_, child, new_parent, new_cost);
}

/// Grows `tree` into `layer` toward q_target from `from` (or the nearest node of the previous
/// layer when from < 0). Returns the new node or -1.
int LayeredArmSearch::extend(int tree, int layer, const JointVector& q_target, int from) {
  const int prev = tree == 0 ? layer - 1 : layer + 1;
  if (layer < 0 || layer >= n_ || prev < 0 || prev >= n_) return -1;
  const auto& cands = layers_[tree][static_cast<std::size_t>(prev)];
  if (cands.empty()) return -1;
  const JointVector& step = steps_[static_cast<std::size_t>(std::min(layer, prev))];
  int near = from;
  if (near < 0) {
    double best = 1e300;
    for (int id : cands) {
      const double d = ((q_target - nodes_[static_cast<std::size_t>(id)].q).cwiseAbs().array() / step.array()).maxCoeff();
      if (d < best) best = d, near = id;
    }
  }
  const JointVector& qn = nodes_[static_cast<std::size_t>(near)].q;
  JointVector q_new = qn + (q_target - qn).cwiseMax(-step).cwiseMin(step);
  q_new = q_new.cwiseMax(lower_).cwiseMin(upper_);
  for (int id : layers_[tree][static_cast<std::size_t>(layer)]) {
    if ((nodes_[static_cast<std::size_t>(id)].q - q_new).cwiseAbs().maxCoeff() < 1e-3) return -1;
  }
  if (!node_free(layer, q_new)) return -1;

  // Until the trees connect, RRT* choose-parent and rewiring are skipped (unless
  // optimize_before_connection): the node hangs from the one it grew from.
  const bool optimize = s_.optimize_before_connection || !connections_.empty();
  std::vector<std::pair<double, int>> parents;
  if (optimize) {
    for (int id : cands) {
      const ArmNode& c = nodes_[static_cast<std::size_t>(id)];
      if (reachable(prev, c.q, layer, q_new)) parents.push_back({c.cost + motion_cost(c.q, q_new), id});
    }
    std::sort(parents.begin(), parents.end());
  } else {
    parents.push_back({nodes_[static_cast<std::size_t>(near)].cost + motion_cost(qn, q_new), near});
  }
  int parent = -1;
  double cost = 0.0;
  const int limit = std::min<int>(static_cast<int>(parents.size()), s_.max_parent_candidates);
  for (int k = 0; k < limit && parent < 0; ++k) {
    const int id = parents[static_cast<std::size_t>(k)].second;
    if (edge_free(prev, nodes_[static_cast<std::size_t>(id)].q, layer, q_new)) {
      parent = id;
      cost = parents[static_cast<std::size_t>(k)].first;
    }
  }
  if (parent < 0) return -1;
  const int id = add_node(tree, layer, q_new, parent, cost);

  const int next = next_layer(tree, layer);
  if (optimize && next >= 0 && next < n_) {  // rewire the next layer through the new node
    for (int m : layers_[tree][static_cast<std::size_t>(next)]) {
      const JointVector qm = nodes_[static_cast<std::size_t>(m)].q;
      if (!reachable(layer, q_new, next, qm)) continue;
      const double c = cost + motion_cost(q_new, qm);
      if (c < nodes_[static_cast<std::size_t>(m)].cost - 1e-9 && edge_free(layer, q_new, next, qm)) reparent(m, id, c);
    }
  }
  return id;
}

/// Tries to join node `id` to the other tree's nodes in the adjacent layer.
bool LayeredArmSearch::try_connect(int id) {
  const ArmNode& a = nodes_[static_cast<std::size_t>(id)];
  const int other = 1 - a.tree;
  const int layer = next_layer(a.tree, a.layer);
  if (layer < 0 || layer >= n_) return false;
  std::vector<std::pair<double, int>> cands;
  for (int m : layers_[other][static_cast<std::size_t>(layer)]) {
    const ArmNode& b = nodes_[static_cast<std::size_t>(m)];
    if (reachable(a.layer, a.q, layer, b.q)) cands.push_back({b.cost + motion_cost(a.q, b.q), m});
  }
  std::sort(cands.begin(), cands.end());
  const int limit = std::min<int>(static_cast<int>(cands.size()), s_.max_connect_candidates);
  for (int k = 0; k < limit; ++k) {
    const int m = cands[static_cast<std::size_t>(k)].second;
    if (edge_free(a.layer, a.q, layer, nodes_[static_cast<std::size_t>(m)].q)) {
      connections_.push_back(a.tree == 0 ? std::make_pair(id, m) : std::make_pair(m, id));
      return true;
    }
  }
  return false;
}

std::vector<JointVector> LayeredArmSearch::path_to_root(int id) const {
  std::vector<JointVector> qs;
  for (int i = id; i >= 0; i = nodes_[static_cast<std::size_t>(i)].parent) qs.push_back(nodes_[static_cast<std::size_t>(i)].q);
  return qs;
}

int LayeredArmSearch::cheapest_in_layer(int tree, int layer) const {
  int best = -1;
  for (int id : layers_[tree][static_cast<std::size_t>(layer)]) {
    if (best < 0 || nodes_[static_cast<std::size_t>(id)].cost < nodes_[static_cast<std::size_t>(best)].cost) best = id;
  }
  return best;
}

void LayeredArmSearch::extract_frontiers(LayeredArmResult& out) const {
  out.forward_q = path_to_root(cheapest_in_layer(0, frontier_[0]));
  std::reverse(out.forward_q.begin(), out.forward_q.end());
  out.backward_q = path_to_root(cheapest_in_layer(1, frontier_[1]));
}

void LayeredArmSearch::extract_solution(LayeredArmResult& out) const {
  double best = 1e300;
  std::pair<int, int> best_pair{-1, -1};
  for (const auto& [f, b] : connections_) {
    const ArmNode& nf = nodes_[static_cast<std::size_t>(f)];
    const ArmNode& nb = nodes_[static_cast<std::size_t>(b)];
    const double c = nf.cost + motion_cost(nf.q, nb.q) + nb.cost;
    if (c < best) best = c, best_pair = {f, b};
  }
  out.q = path_to_root(best_pair.first);
  std::reverse(out.q.begin(), out.q.end());
  const std::vector<JointVector> tail = path_to_root(best_pair.second);
  out.q.insert(out.q.end(), tail.begin(), tail.end());
  out.cost = best;
}

void LayeredArmSearch::shortcut(const planner::Deadline& deadline, LayeredArmResult& out) {
  std::vector<JointVector>& q = out.q;
  if (n_ < 3 || static_cast<int>(q.size()) != n_) return;
  std::vector<JointVector> line;
  for (int a = 0; a < s_.shortcut_attempts && !deadline.expired(); ++a) {
    const int i = std::uniform_int_distribution<int>(0, n_ - 3)(rng_);
    const int j = std::uniform_int_distribution<int>(i + 2, std::min(n_ - 1, i + s_.shortcut_max_layers))(rng_);
    double old_cost = 0.0;
    for (int k = i; k < j; ++k) old_cost += motion_cost(q[static_cast<std::size_t>(k)], q[static_cast<std::size_t>(k) + 1]);
    const JointVector& qi = q[static_cast<std::size_t>(i)];
    const JointVector& qj = q[static_cast<std::size_t>(j)];
    if (motion_cost(qi, qj) >= old_cost - 1e-9) continue;  // already straight
    line.assign(static_cast<std::size_t>(j - i + 1), qi);
    bool ok = true;
    for (int k = i + 1; ok && k <= j; ++k) {
      line[static_cast<std::size_t>(k - i)] = qi + (static_cast<double>(k - i) / (j - i)) * (qj - qi);
      ok = reachable(k - 1, line[static_cast<std::size_t>(k - i - 1)], k, line[static_cast<std::size_t>(k - i)]);
    }
    for (int k = i + 1; ok && k < j; ++k) ok = node_free(k, line[static_cast<std::size_t>(k - i)]);
    for (int k = i; ok && k < j; ++k)
      ok = edge_free(k, line[static_cast<std::size_t>(k - i)], k + 1, line[static_cast<std::size_t>(k - i + 1)]);
    if (!ok) continue;
    for (int k = i + 1; k < j; ++k) q[static_cast<std::size_t>(k)] = line[static_cast<std::size_t>(k - i)];
  }
  out.cost = 0.0;
  for (int k = 0; k + 1 < n_; ++k) out.cost += motion_cost(q[static_cast<std::size_t>(k)], q[static_cast<std::size_t>(k) + 1]);
}

}  // namespace porter::frontend::detail
