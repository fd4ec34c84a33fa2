#include <algorithm>
#include <cmath>

#include "layered_arm_search.hpp"

namespace porter::frontend::detail {

JointVector LayeredArmSearch::sample_q() {
  JointVector q;
  for (int j = 0; j < kNumArmJoints; ++j) q[j] = std::uniform_real_distribution<double>(lower_[j], upper_[j])(rng_);
  return q;
}

int LayeredArmSearch::sample_layer(int tree) {
  int lo = 1, hi = n_ - 2;
  if (tree == 0) hi = std::min(hi, frontier_[0] + 1);
  else lo = std::max(lo, frontier_[1] - 1);
  if (std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < s_.frontier_bias) {
    if (tree == 0) lo = std::max(lo, hi - s_.frontier_window);
    else hi = std::min(hi, lo + s_.frontier_window);
  }
  return std::uniform_int_distribution<int>(lo, std::max(lo, hi))(rng_);
}

int LayeredArmSearch::random_node_in(const std::vector<int>& ids) {
  return ids[std::uniform_int_distribution<std::size_t>(0, ids.size() - 1)(rng_)];
}

/// RRT-Connect style: chains a node near the tree's frontier toward chain_target().
void LayeredArmSearch::greedy_chain(int tree) {
  const int layer0 = sample_layer(tree);
  const int prev = tree == 0 ? layer0 - 1 : layer0 + 1;
  const auto& start_layer = layers_[tree][static_cast<std::size_t>(prev)];
  if (start_layer.empty()) return;
  int cur = random_node_in(start_layer);
  chain(tree, cur, chain_target(tree, cur));
}

/// Heads for a corridor configuration of the next blocked stretch ahead (corridor_target_bias,
/// when one is known), holds the node's configuration (hold_bias) or heads for a node of the
/// other tree a few layers ahead.
JointVector LayeredArmSearch::chain_target(int tree, int node) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const int layer = nodes_[static_cast<std::size_t>(node)].layer;
  const Stretch* ahead = nullptr;
  for (const Stretch& st : stretches_) {
    if (st.targets.empty()) continue;
    if (tree == 0 && st.first > layer && (!ahead || st.first < ahead->first)) ahead = &st;
    if (tree == 1 && st.last < layer && (!ahead || st.last > ahead->last)) ahead = &st;
  }
  if (ahead && u01(rng_) < s_.corridor_target_bias)
    return ahead->targets[std::uniform_int_distribution<std::size_t>(0, ahead->targets.size() - 1)(rng_)];
  if (u01(rng_) < s_.hold_bias) return nodes_[static_cast<std::size_t>(node)].q;
  // A node of the other tree one to three layers ahead (its frontier when that is farther).
  const int ahead_layers = std::uniform_int_distribution<int>(1, 3)(rng_);
  const int target_layer = tree == 0 ? std::max(std::min(layer + ahead_layers, n_ - 1), frontier_[1])
                                     : std::min(std::max(layer - ahead_layers, 0), frontier_[0]);
  return nodes_[static_cast<std::size_t>(random_node_in(layers_[1 - tree][static_cast<std::size_t>(target_layer)]))].q;
}

/// Extends layer after layer from `node` toward `target` until a step fails or connects. A
/// step that fails moving every joint is retried (chain_retries times) moving a random subset
/// of the joints only: big payloads often need the joints to move in some order.
void LayeredArmSearch::chain(int tree, int node, const JointVector& target) {
  int cur = node;
  while (true) {
    const int layer = next_layer(tree, nodes_[static_cast<std::size_t>(cur)].layer);
    if (layer < 1 || layer > n_ - 2) return;
    int id = extend(tree, layer, target, cur);
    for (int r = 0; id < 0 && r < s_.chain_retries; ++r) {
      JointVector partial = nodes_[static_cast<std::size_t>(cur)].q;
      for (int j = 0; j < kNumArmJoints; ++j)
        if (std::uniform_int_distribution<int>(0, 1)(rng_)) partial[j] = target[j];
      id = extend(tree, layer, partial, cur);
    }
    if (id < 0 || try_connect(id)) return;
    cur = id;
  }
}

/// After a new node that reached the tree's frontier: keep going (extend-then-connect).
void LayeredArmSearch::continue_chain(int tree, int node) {
  if (nodes_[static_cast<std::size_t>(node)].layer != frontier_[tree]) return;
  chain(tree, node, chain_target(tree, node));
}

/// Extends a random node of a layer into the next one with one or two of its joints
/// re-drawn uniformly within the limits (the others kept): narrow passages usually need a
/// few joints to change while the rest hold.
void LayeredArmSearch::local_step(int tree) {
  const int layer = sample_layer(tree);
  const int prev = tree == 0 ? layer - 1 : layer + 1;
  const auto& cands = layers_[tree][static_cast<std::size_t>(prev)];
  if (cands.empty()) return;
  const int from = random_node_in(cands);
  JointVector q = nodes_[static_cast<std::size_t>(from)].q;
  const int changes = std::uniform_int_distribution<int>(1, 2)(rng_);
  for (int c = 0; c < changes; ++c) {
    const int j = std::uniform_int_distribution<int>(0, kNumArmJoints - 1)(rng_);
    q[j] = std::uniform_real_distribution<double>(lower_[j], upper_[j])(rng_);
  }
  const int id = extend(tree, layer, q, from);
  if (id >= 0 && !try_connect(id)) continue_chain(tree, id);
}

/// Runs of layers where neither the start's nor the goal's arm configuration fits: the
/// narrow passages that need the arm to change.
void LayeredArmSearch::find_stretches() {
  const bool same = p_.q_start == p_.q_goal;
  int open = -1;
  for (int l = 1; l < n_ - 1; ++l) {
    const bool blocked = !node_free(l, p_.q_start) && (same || !node_free(l, p_.q_goal));
    if (blocked && open < 0) open = l;
    if (!blocked && open >= 0) stretches_.push_back({open, l - 1, 0, 0, {}});
    if (!blocked) open = -1;
  }
  if (open >= 0) stretches_.push_back({open, n_ - 2, 0, 0, {}});
  // The margin: layers within corridor_margin_m of base travel before and after the stretch.
  auto gap = [&](int a, int b) {
    const BasePose& p = p_.bases[static_cast<std::size_t>(a)];
    const BasePose& q = p_.bases[static_cast<std::size_t>(b)];
    return std::hypot(q.x_m - p.x_m, q.y_m - p.y_m);
  };
  for (Stretch& st : stretches_) {
    st.lo = st.first;
    for (double d = 0.0; st.lo > 1 && (d += gap(st.lo - 1, st.lo)) <= s_.corridor_margin_m + 1e-9;) --st.lo;
    st.hi = st.last;
    for (double d = 0.0; st.hi < n_ - 2 && (d += gap(st.hi, st.hi + 1)) <= s_.corridor_margin_m + 1e-9;) ++st.hi;
  }
}

/// For a random blocked stretch: draws configurations until one is free at every layer of the
/// stretch and along the held motion through it (while fewer than max_corridor_targets are
/// known, and always while none is), then lets one tree chain toward a known one from a few
/// layers outside the stretch, far enough for the arm to get there in the open. False when there
/// is no stretch.
bool LayeredArmSearch::corridor_step() {
  if (stretches_.empty() || s_.max_corridor_targets == 0) return false;
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  Stretch& st = stretches_[std::uniform_int_distribution<std::size_t>(0, stretches_.size() - 1)(rng_)];
  if (static_cast<int>(st.targets.size()) < s_.max_corridor_targets && (st.targets.empty() || u01(rng_) < 0.25)) {
    // The shape must also fit a margin around the stretch: the payload can reach past the base.
    const int lo = st.lo, hi = st.hi;
    const int mid = (st.first + st.last) / 2;
    for (int draw = 0; draw < s_.corridor_draws; ++draw) {
      const JointVector q = sample_q();
      bool ok = true;
      for (int k = 0; ok && k <= 2 * (hi - lo + 1); ++k) {  // middle layers first
        const int l = k % 2 == 0 ? mid + k / 2 : mid - (k + 1) / 2;
        if (l >= lo && l <= hi) ok = node_free(l, q);
      }
      for (int l = lo; ok && l < hi; ++l) ok = edge_free(l, q, l + 1, q);
      if (ok) {
        st.targets.push_back(q);
        break;
      }
    }
    if (st.targets.empty()) return true;
  }
  const JointVector target = st.targets[std::uniform_int_distribution<std::size_t>(0, st.targets.size() - 1)(rng_)];
  const int tree = std::uniform_int_distribution<int>(0, 1)(rng_);
  const JointVector& root_q = tree == 0 ? p_.q_start : p_.q_goal;
  const JointVector& step = steps_[static_cast<std::size_t>(std::max(0, std::min(st.first, n_ - 2)))];
  const int needed = static_cast<int>(std::ceil(((target - root_q).cwiseAbs().array() / step.array()).maxCoeff())) + 1 +
                     std::uniform_int_distribution<int>(0, 2)(rng_);
  int layer = tree == 0 ? std::clamp(st.first - needed, 0, frontier_[0]) : std::clamp(st.last + needed, frontier_[1], n_ - 1);
  const auto& from = layers_[tree][static_cast<std::size_t>(layer)];
  if (from.empty()) return true;
  chain(tree, random_node_in(from), target);
  return true;
}

}  // namespace porter::frontend::detail
