#include "porter/frontend/whole_body_rrt.hpp"
#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>

#include "porter/planner/deadline.hpp"
#include "tree_rewire.hpp"

namespace porter::frontend {

bool validate_settings(const WholeBodyRrtSettings& s, std::string* why) {
  auto bad = [&](const char* field) {
    if (why) *why = std::string("WholeBodyRrtSettings.") + field + " out of range";
    return false;
  };
  if (!(s.max_extend_m > 0.0)) return bad("max_extend_m");
  if (!(s.max_extend_q_rad > 0.0)) return bad("max_extend_q_rad");
  if (!(s.joint_cost_weight_m_per_rad >= 0.0)) return bad("joint_cost_weight_m_per_rad");
  if (!(s.reverse_cost_factor >= 1.0)) return bad("reverse_cost_factor");
  if (!(s.gear_switch_cost_m >= 0.0)) return bad("gear_switch_cost_m");
  if (!(s.goal_bias >= 0.0 && s.goal_bias <= 1.0)) return bad("goal_bias");
  if (!(s.sampling_margin_m >= 0.0)) return bad("sampling_margin_m");
  if (s.neighbours < 1) return bad("neighbours");
  if (!(s.edge_step_m > 0.0)) return bad("edge_step_m");
  if (!(s.edge_q_step_rad > 0.0)) return bad("edge_q_step_rad");
  if (s.refine_iterations < 0) return bad("refine_iterations");
  if (s.max_iterations < 1) return bad("max_iterations");
  return true;
}

WholeBodyRrt::WholeBodyRrt(const RobotModel& model, const planner::CollisionChecker& checker,
                           double turning_radius_m, const Eigen::AlignedBox2d& map_bounds_xy_W,
                           WholeBodyRrtSettings settings)
    : model_(model), checker_(checker), radius_m_(turning_radius_m), bounds_(map_bounds_xy_W), settings_(settings) {}

namespace {

constexpr int kSpaceDim = 2 + kNumArmJoints;
using SpaceVector = Eigen::Matrix<double, kSpaceDim, 1>;

struct WbNode {
  RobotConfiguration c;
  int parent = -1;
  double cost = 0.0;
  int eta_in = 0;  // driving direction at the end of the edge from the parent (0: root)
  std::vector<int> children;
};

/// First and last driving direction along a Reeds–Shepp curve (0 when it has no length).
std::pair<int, int> end_directions(const RsPath& path) {
  int first = 0, last = 0;
  for (int i = 0; i < path.num_segments; ++i) {
    const double len = path.segments[static_cast<std::size_t>(i)].length_m;
    if (len == 0.0) continue;
    last = len > 0.0 ? 1 : -1;
    if (first == 0) first = last;
  }
  return {first, last};
}

class WbSearch {
 public:
  WbSearch(const RobotModel& model, const planner::CollisionChecker& checker, double radius,
           const Eigen::AlignedBox2d& box, const WholeBodyRrtSettings& s, std::uint64_t seed, StageReport& rep)
      : checker_(checker), s_(s), rs_(radius), box_(box), rng_(seed), rep_(rep),
        lower_(model.lower_limits()), upper_(model.upper_limits()) {}

  /// Samples of the edge a -> b (first = a, last = b), with the arc length where each lies.
  void edge_samples(const RobotConfiguration& a, const RobotConfiguration& b, std::vector<WholeBodySample>* out) {
    out->clear();
    const RsPath path = rs_.shortest(a.base, b.base);
    const JointVector dq = b.q_rad - a.q_rad;
    const int nq = std::max(1, static_cast<int>(std::ceil(dq.cwiseAbs().maxCoeff() / s_.edge_q_step_rad - 1e-9)));
    out->push_back({a, 0});
    if (path.length_m < 1e-9) {
      for (int k = 1; k <= nq; ++k) out->push_back({{a.base, a.q_rad + dq * (static_cast<double>(k) / nq)}, 0});
      out->back().config = b;
      return;
    }
    const double step = std::min(s_.edge_step_m, path.length_m / nq);
    double s_done = 0.0;
    BasePose p = a.base;
    for (int i = 0; i < path.num_segments; ++i) {
      const RsSegment& seg = path.segments[static_cast<std::size_t>(i)];
      const int eta = seg.length_m >= 0.0 ? 1 : -1;
      const double len = std::abs(seg.length_m);
      const int n = std::max(1, static_cast<int>(std::ceil(len / step - 1e-9)));
      const double kappa = seg.kind == RsSegment::Kind::kLeft ? 1.0 / path.radius_m
                           : seg.kind == RsSegment::Kind::kRight ? -1.0 / path.radius_m : 0.0;
      for (int k = 1; k <= n; ++k) {
        const double s = s_done + len * k / n;
        out->push_back({{drive_arc(p, kappa, eta * len * k / n), a.q_rad + dq * (s / path.length_m)}, eta});
      }
      p = out->back().config.base;
      s_done += len;
    }
    out->back().config = b;  // exact end
  }

  /// Cost of the edge from node `from` to b, including a gear switch where it starts against the
  /// direction `from` was reached in. (A rewired node's children keep the junction cost they were
  /// added with: RRT*'s usual approximation for direction-dependent costs.)
  double edge_cost(const WbNode& from, const RobotConfiguration& b) {
    const RsPath path = rs_.shortest(from.c.base, b.base);
    const int first = end_directions(path).first;
    const double junction = from.eta_in != 0 && first != 0 && first != from.eta_in ? s_.gear_switch_cost_m : 0.0;
    return junction + path_cost(path) + s_.joint_cost_weight_m_per_rad * (b.q_rad - from.c.q_rad).norm();
  }

  /// Reverse driving and direction changes cost extra: each gear switch becomes a segment joint
  /// of the mid-end, and a path of many is slow and fragile.
  double path_cost(const RsPath& path) const {
    if (!std::isfinite(path.length_m)) return path.length_m;
    double cost = s_.gear_switch_cost_m * path.cusps();
    for (int i = 0; i < path.num_segments; ++i) {
      const double len = path.segments[static_cast<std::size_t>(i)].length_m;
      cost += len >= 0.0 ? len : -s_.reverse_cost_factor * len;
    }
    return cost;
  }

  bool node_free(const RobotConfiguration& c) {
    if (!box_.contains(Eigen::Vector2d(c.base.x_m, c.base.y_m))) return false;
    ++rep_.collision_checks;
    return !checker_.check(c);
  }

  bool edge_free(const RobotConfiguration& a, const RobotConfiguration& b) {
    edge_samples(a, b, &scratch_);
    for (std::size_t i = 1; i < scratch_.size(); ++i) {
      ++rep_.collision_checks;
      if (checker_.check_motion(scratch_[i - 1].config, scratch_[i].config)) return false;
    }
    return true;
  }

  double cheap_distance(const RobotConfiguration& a, const RobotConfiguration& b) const {
    return std::hypot(b.base.x_m - a.base.x_m, b.base.y_m - a.base.y_m) +
           0.5 * rs_.turning_radius_m() * std::abs(planner::wrap_angle_rad(b.base.yaw_rad - a.base.yaw_rad)) +
           s_.joint_cost_weight_m_per_rad * (b.q_rad - a.q_rad).norm();
  }

  SpaceVector to_space(const RobotConfiguration& c) const {
    SpaceVector v;
    v << c.base.x_m, c.base.y_m, s_.joint_cost_weight_m_per_rad * c.q_rad;
    return v;
  }

  RobotConfiguration sample_uniform() {
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    RobotConfiguration c;
    c.base.x_m = box_.min().x() + u01(rng_) * box_.sizes().x();
    c.base.y_m = box_.min().y() + u01(rng_) * box_.sizes().y();
    c.base.yaw_rad = -M_PI + 2.0 * M_PI * u01(rng_);
    for (int j = 0; j < kNumArmJoints; ++j) c.q_rad[j] = lower_[j] + u01(rng_) * (upper_[j] - lower_[j]);
    return c;
  }

  /// Uniform in the informed set when the joint weight allows it; otherwise uniform.
  RobotConfiguration sample_informed(const RobotConfiguration& start, const RobotConfiguration& goal, double c_best) {
    const double w = s_.joint_cost_weight_m_per_rad;
    const SpaceVector vs = to_space(start), vg = to_space(goal);
    const double c_min = (vg - vs).norm();
    if (w <= 0.0 || !(c_best > c_min)) return sample_uniform();
    const SpaceVector center = 0.5 * (vs + vg);
    SpaceVector a1 = c_min > 1e-12 ? SpaceVector((vg - vs) / c_min) : SpaceVector::Unit(0);
    const SpaceVector u = a1 - SpaceVector::Unit(0);
    const double un = u.squaredNorm();
    std::normal_distribution<double> n01(0.0, 1.0);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const double r1 = 0.5 * c_best, r2 = 0.5 * std::sqrt(c_best * c_best - c_min * c_min);
    for (int attempt = 0; attempt < 20; ++attempt) {
      SpaceVector b;
      for (int i = 0; i < kSpaceDim; ++i) b[i] = n01(rng_);
      b *= std::pow(u01(rng_), 1.0 / kSpaceDim) / std::max(1e-12, b.norm());
      b[0] *= r1;
      b.tail<kSpaceDim - 1>() *= r2;
      if (un > 1e-24) b -= (2.0 * u.dot(b) / un) * u;  // Householder reflection: e1 -> a1
      const SpaceVector v = center + b;
      RobotConfiguration c;
      c.base = {v[0], v[1], -M_PI + 2.0 * M_PI * u01(rng_)};
      c.q_rad = v.tail<kNumArmJoints>() / w;
      if (box_.contains(Eigen::Vector2d(v[0], v[1])) && (c.q_rad.array() >= lower_.array()).all() &&
          (c.q_rad.array() <= upper_.array()).all())
        return c;
    }
    return sample_uniform();
  }

  int arrival_direction(int parent, const RobotConfiguration& c) {
    if (parent < 0) return 0;
    const int last = end_directions(rs_.shortest(nodes_[static_cast<std::size_t>(parent)].c.base, c.base)).second;
    return last != 0 ? last : nodes_[static_cast<std::size_t>(parent)].eta_in;
  }

  void reparent(int child, int new_parent, double new_cost) {
    reparent_subtree(nodes_, child, new_parent, new_cost);
    nodes_[static_cast<std::size_t>(child)].eta_in = arrival_direction(new_parent, nodes_[static_cast<std::size_t>(child)].c);
  }

  int add_node(const RobotConfiguration& c, int parent, double cost) {
    WbNode n;
    n.c = c;
    n.parent = parent;
    n.cost = cost;
    n.eta_in = arrival_direction(parent, c);
    nodes_.push_back(std::move(n));
    const int id = static_cast<int>(nodes_.size()) - 1;
    if (parent >= 0) nodes_[static_cast<std::size_t>(parent)].children.push_back(id);
    return id;
  }

  planner::Status run(const RobotConfiguration& start, const RobotConfiguration& goal, const planner::Deadline& deadline,
                    WholeBodyRrtResult& out) {
    if (!node_free(start)) return planner::Status::kInvalidStart;
    if (!node_free(goal)) return planner::Status::kInvalidGoal;
    add_node(start, -1, 0.0);
    int goal_id = -1;
    auto try_goal = [&](int from) {
      const RobotConfiguration& c = nodes_[static_cast<std::size_t>(from)].c;
      if (std::hypot(goal.base.x_m - c.base.x_m, goal.base.y_m - c.base.y_m) > 2.0 * s_.max_extend_m) return;
      const double cost = nodes_[static_cast<std::size_t>(from)].cost + edge_cost(nodes_[static_cast<std::size_t>(from)], goal);
      if (goal_id >= 0 && cost >= nodes_[static_cast<std::size_t>(goal_id)].cost - 1e-9) return;
      if (!edge_free(c, goal)) return;
      if (goal_id < 0) goal_id = add_node(goal, from, cost);
      else reparent(goal_id, from, cost);
    };
    try_goal(0);
    std::int64_t first_solution_it = goal_id >= 0 ? 0 : -1;
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    planner::Status status = planner::Status::kTimeout;
    std::vector<std::pair<double, int>> near;
    while (true) {
      if (goal_id >= 0) {
        if (first_solution_it < 0) first_solution_it = rep_.iterations;
        if (rep_.iterations - first_solution_it >= s_.refine_iterations) break;
      }
      if (rep_.iterations >= s_.max_iterations || deadline.expired()) break;
      ++rep_.iterations;
      const RobotConfiguration target = u01(rng_) < s_.goal_bias ? goal
                                        : goal_id >= 0 ? sample_informed(start, goal, nodes_[static_cast<std::size_t>(goal_id)].cost)
                                                       : sample_uniform();
      near.clear();
      for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (static_cast<int>(i) == goal_id) continue;
        near.push_back({cheap_distance(nodes_[i].c, target), static_cast<int>(i)});
      }
      const std::size_t k = std::min<std::size_t>(near.size(), static_cast<std::size_t>(s_.neighbours));
      std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(k), near.end());
      const RobotConfiguration& from = nodes_[static_cast<std::size_t>(near[0].second)].c;
      RobotConfiguration c_new;
      const RsPath path = rs_.shortest(from.base, target.base);
      double f = 1.0;
      if (path.length_m > s_.max_extend_m) {
        f = s_.max_extend_m / path.length_m;
        c_new.base = rs_pose_at(from.base, path, s_.max_extend_m);
      } else {
        c_new.base = target.base;
      }
      JointVector dq = f * (target.q_rad - from.q_rad);
      const double dq_max = dq.cwiseAbs().maxCoeff();
      if (dq_max > s_.max_extend_q_rad) dq *= s_.max_extend_q_rad / dq_max;
      c_new.q_rad = (from.q_rad + dq).cwiseMax(lower_).cwiseMin(upper_);
      if (!node_free(c_new)) continue;
      // Neighbours of the new node (by the cheap metric), cheapest valid parent first.
      near.clear();
      for (std::size_t i = 0; i < nodes_.size(); ++i) {
        if (static_cast<int>(i) == goal_id) continue;
        near.push_back({cheap_distance(nodes_[i].c, c_new), static_cast<int>(i)});
      }
      const std::size_t kn = std::min<std::size_t>(near.size(), static_cast<std::size_t>(s_.neighbours));
      std::partial_sort(near.begin(), near.begin() + static_cast<std::ptrdiff_t>(kn), near.end());
      near.resize(kn);
      std::vector<std::pair<double, int>> parents;
      for (const auto& [d, id] : near)
        parents.push_back({nodes_[static_cast<std::size_t>(id)].cost + edge_cost(nodes_[static_cast<std::size_t>(id)], c_new), id});
      std::sort(parents.begin(), parents.end());
      int parent = -1;
      double cost = 0.0;
      for (const auto& [c, id] : parents) {
        if (edge_free(nodes_[static_cast<std::size_t>(id)].c, c_new)) {
          parent = id;
          cost = c;
          break;
        }
      }
      if (parent < 0) continue;
      const int id_new = add_node(c_new, parent, cost);
      for (const auto& [d, id] : near) {
        if (id == parent) continue;
        const double c = cost + edge_cost(nodes_[static_cast<std::size_t>(id_new)], nodes_[static_cast<std::size_t>(id)].c);
        if (c < nodes_[static_cast<std::size_t>(id)].cost - 1e-9 && edge_free(c_new, nodes_[static_cast<std::size_t>(id)].c))
          reparent(id, id_new, c);
      }
      try_goal(id_new);
    }
    if (goal_id < 0) return status;
    extract(goal_id, out);
    return planner::Status::kSuccess;
  }

  void extract(int goal_id, WholeBodyRrtResult& out) {
    std::vector<int> chain;
    for (int i = goal_id; i >= 0; i = nodes_[static_cast<std::size_t>(i)].parent) chain.push_back(i);
    std::reverse(chain.begin(), chain.end());
    out.path.clear();
    out.path.push_back({nodes_[static_cast<std::size_t>(chain[0])].c, 0});
    for (std::size_t i = 1; i < chain.size(); ++i) {
      edge_samples(nodes_[static_cast<std::size_t>(chain[i - 1])].c, nodes_[static_cast<std::size_t>(chain[i])].c, &scratch_);
      for (std::size_t k = 1; k < scratch_.size(); ++k) {
        const RobotConfiguration& a = out.path.back().config;
        const RobotConfiguration& b = scratch_[k].config;
        const bool same = std::abs(a.base.x_m - b.base.x_m) < 1e-12 && std::abs(a.base.y_m - b.base.y_m) < 1e-12 &&
                          std::abs(planner::wrap_angle_rad(a.base.yaw_rad - b.base.yaw_rad)) < 1e-12 &&
                          (a.q_rad - b.q_rad).cwiseAbs().maxCoeff() < 1e-12;
        if (!same) out.path.push_back(scratch_[k]);
      }
    }
    // Samples reached without base motion keep the direction around them.
    int last = 0;
    for (auto& smp : out.path) {
      if (smp.eta == 0) smp.eta = last;
      else last = smp.eta;
    }
    int next = 1;
    for (auto it = out.path.rbegin(); it != out.path.rend(); ++it) {
      if (it->eta == 0) it->eta = next;
      else next = it->eta;
    }
    if (out.path.size() > 1) out.path.front().eta = out.path[1].eta;
    out.cost = nodes_[static_cast<std::size_t>(goal_id)].cost;
  }

 private:
  const planner::CollisionChecker& checker_;
  const WholeBodyRrtSettings& s_;
  ReedsShepp rs_;
  Eigen::AlignedBox2d box_;
  std::mt19937_64 rng_;
  StageReport& rep_;
  JointVector lower_, upper_;
  std::vector<WbNode> nodes_;
  std::vector<WholeBodySample> scratch_;
};

}  // namespace

WholeBodyRrtResult WholeBodyRrt::plan(const RobotConfiguration& start, const RobotConfiguration& goal,
                                      const planner::Deadline& budget, std::uint64_t seed) const {
  const planner::Deadline deadline = budget.from_now();
  WholeBodyRrtResult out;
  out.report.ran = true;
  Eigen::AlignedBox2d box(Eigen::Vector2d(start.base.x_m, start.base.y_m));
  box.extend(Eigen::Vector2d(goal.base.x_m, goal.base.y_m));
  box.min().array() -= settings_.sampling_margin_m;
  box.max().array() += settings_.sampling_margin_m;
  box = box.intersection(bounds_);
  WbSearch search(model_, checker_, radius_m_, box, settings_, seed, out.report);
  out.report.status = search.run(start, goal, deadline, out);
  switch (out.report.status) {
    case planner::Status::kInvalidStart: out.report.message = "start configuration in collision or outside the map"; break;
    case planner::Status::kInvalidGoal: out.report.message = "goal configuration in collision or outside the map"; break;
    case planner::Status::kTimeout: out.report.message = "no connection within the budget"; break;
    default: break;
  }
  out.report.elapsed_s = deadline.elapsed_s();
  return out;
}

}  // namespace porter::frontend
