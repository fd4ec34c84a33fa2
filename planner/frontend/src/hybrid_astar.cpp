#include "porter/frontend/hybrid_astar.hpp"
#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <queue>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "base_motion.hpp"
#include "porter/planner/collision/kernel_kinematics.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::frontend {

bool validate_settings(const HybridAStarSettings& s, std::string* why) {
  auto bad = [&](const char* field) {
    if (why) *why = std::string("HybridAStarSettings.") + field + " out of range";
    return false;
  };
  if (!(s.xy_resolution_m >= 0.02 && s.xy_resolution_m <= 1.0)) return bad("xy_resolution_m");
  if (s.yaw_bins < 8 || s.yaw_bins > 360) return bad("yaw_bins");
  if (!(s.step_length_m > std::sqrt(2.0) * s.xy_resolution_m && s.step_length_m <= 2.0)) return bad("step_length_m");
  if (s.steering_samples < 3 || s.steering_samples > 15 || s.steering_samples % 2 == 0) return bad("steering_samples");
  if (!(s.turning_radius_m >= 0.0 && s.turning_radius_m < 100.0)) return bad("turning_radius_m");
  if (!(s.collision_step_m >= 0.005 && s.collision_step_m <= 0.5)) return bad("collision_step_m");
  if (!(s.reverse_cost_factor >= 1.0)) return bad("reverse_cost_factor");
  if (!(s.gear_switch_cost_m >= 0.0)) return bad("gear_switch_cost_m");
  if (!(s.steering_cost >= 0.0)) return bad("steering_cost");
  if (!(s.steering_change_cost >= 0.0)) return bad("steering_change_cost");
  if (!(s.heuristic_weight >= 1.0 && s.heuristic_weight <= 10.0)) return bad("heuristic_weight");
  if (!(s.rs_heuristic_range_m >= 0.0)) return bad("rs_heuristic_range_m");
  if (!(s.analytic_expansion_range_m >= 0.0)) return bad("analytic_expansion_range_m");
  if (s.analytic_expansion_interval < 1) return bad("analytic_expansion_interval");
  if (s.max_shot_cusps < 0 || s.max_shot_cusps > 3) return bad("max_shot_cusps");
  if (!(s.arm_blocked_cost_factor >= 0.0)) return bad("arm_blocked_cost_factor");
  if (s.narrow_shape_draws < 0) return bad("narrow_shape_draws");
  if (!(s.heuristic_resolution_m >= 0.02 && s.heuristic_resolution_m <= 1.0)) return bad("heuristic_resolution_m");
  if (s.max_expansions < 1) return bad("max_expansions");
  return true;
}

HybridAStar::HybridAStar(const RobotModel& model, const planner::CollisionChecker& checker,
                         HybridAStarSettings settings)
    : model_(model), checker_(checker), settings_(settings),
      radius_m_(std::max(settings.turning_radius_m, model.base.min_turning_radius_m)),
      disc_(base_inscribed_disc(model)), base_reach_m_(detail::base_reach_m(model)),
      chord_reach_m_(planner::compute_chain_radii(model).reach_m),
      rs_(std::make_unique<ReedsShepp>(radius_m_)),
      narrow_candidates_(narrow_shape_candidates()) {}

HybridAStar::~HybridAStar() = default;

void HybridAStar::set_map(const OccupancyGrid& occupancy_W) {
  grid_.build(occupancy_W, disc_, settings_.heuristic_resolution_m);
  const Eigen::AlignedBox3d b = occupancy_W.bounds_W();
  origin_ = b.min().head<2>();
  nx_ = std::max(1, static_cast<int>(std::ceil((b.max().x() - origin_.x()) / settings_.xy_resolution_m)));
  ny_ = std::max(1, static_cast<int>(std::ceil((b.max().y() - origin_.y()) / settings_.xy_resolution_m)));
  const std::size_t cells = static_cast<std::size_t>(nx_) * ny_ * settings_.yaw_bins;
  stamp_.assign(cells, 0);
  cell_node_.assign(cells, -1);
  generation_ = 0;
  have_map_ = true;
}

namespace {

struct Node {
  BasePose pose;
  double g = 0.0;
  std::int32_t parent = -1;
  std::int32_t cell = -1;
  std::int8_t eta = 0;    // direction of the motion reaching it; 0 at the start
  std::int8_t steer = 0;  // steering index of that motion
  bool closed = false;
};

struct OpenItem {
  double f;
  std::int32_t node;
  bool operator>(const OpenItem& o) const { return f > o.f || (f == o.f && node > o.node); }
};

}  // namespace

std::vector<JointVector> HybridAStar::narrow_shape_candidates() const {
  // Seeded from the settings only: the same candidates for every plan() of this object.
  std::mt19937_64 rng(0x6a09e667f3bcc909ull);
  const JointVector lo = model_.lower_limits(), hi = model_.upper_limits();
  KinematicsWorkspace ws;
  std::vector<std::pair<double, JointVector>> drawn;
  for (int d = 0; d < settings_.narrow_shape_draws; ++d) {
    RobotConfiguration c{BasePose{}, JointVector::Zero()};
    for (int j = 0; j < kNumArmJoints; ++j) c.q_rad[j] = std::uniform_real_distribution<double>(lo[j], hi[j])(rng);
    forward_kinematics(model_, c, ws);  // base at the origin: world = base frame
    double width = 0.0;
    for (int l = 1; l < kNumLinks; ++l) {
      const Link& link = model_.links[static_cast<std::size_t>(l)];
      if (link.shapes.empty()) continue;
      const Eigen::Vector3d p = ws.T_W_L[static_cast<std::size_t>(l)] * link.bounding_center;
      width = std::max(width, std::abs(p.y()) + link.bounding_radius_m);
    }
    drawn.emplace_back(width, c.q_rad);
  }
  std::stable_sort(drawn.begin(), drawn.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<JointVector> out;
  for (const auto& d : drawn) out.push_back(d.second);
  return out;
}

std::optional<JointVector> HybridAStar::narrow_shape(const BasePose& at, StageReport& rep) const {
  for (const JointVector& q : narrow_candidates_) {
    ++rep.collision_checks;
    if (!checker_.check(RobotConfiguration{at, q})) return q;  // must at least fit where the robot starts
  }
  return std::nullopt;
}

HybridAStarResult HybridAStar::plan(const RobotConfiguration& start, const RobotConfiguration& goal,
                                    const planner::Deadline& budget) {
  const planner::Deadline deadline = budget.from_now();
  HybridAStarResult result;
  StageReport& rep = result.report;
  rep.ran = true;
  auto finish = [&](planner::Status st, std::string msg) {
    rep.status = st;
    rep.message = std::move(msg);
    rep.elapsed_s = deadline.elapsed_s();
    return result;
  };
  if (!have_map_) return finish(planner::Status::kNoMap, "HybridAStar::set_map() was not called");
  const HybridAStarSettings& s = settings_;
  ++rep.collision_checks;
  if (checker_.check_base(start.base)) return finish(planner::Status::kInvalidStart, "start base pose in collision");
  ++rep.collision_checks;
  if (checker_.check_base(goal.base)) return finish(planner::Status::kInvalidGoal, "goal base pose in collision");
  grid_.set_goal(goal.base.x_m, goal.base.y_m);
  if (!std::isfinite(grid_.distance(start.base.x_m, start.base.y_m)))
    return finish(planner::Status::kNoPath, "goal unreachable: no corridor wide enough for the base footprint");

  auto cell_of = [&](const BasePose& p) -> std::int32_t {
    const double fx = (p.x_m - origin_.x()) / s.xy_resolution_m, fy = (p.y_m - origin_.y()) / s.xy_resolution_m;
    if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ && fy < ny_)) return -1;
    int iyaw = static_cast<int>(std::floor((planner::wrap_angle_rad(p.yaw_rad) + M_PI) / (2.0 * M_PI) * s.yaw_bins));
    iyaw = ((iyaw % s.yaw_bins) + s.yaw_bins) % s.yaw_bins;
    return static_cast<std::int32_t>((static_cast<std::int64_t>(iyaw) * ny_ + static_cast<int>(fy)) * nx_ +
                                     static_cast<int>(fx));
  };
  auto heuristic = [&](const BasePose& p) {
    const double dg = grid_.distance(p.x_m, p.y_m);
    const double de = std::hypot(goal.base.x_m - p.x_m, goal.base.y_m - p.y_m);
    const double drs = de < s.rs_heuristic_range_m ? rs_->distance(p, goal.base) : de;
    return std::max(dg, drs);
  };
  const bool same_arm = (start.q_rad - goal.q_rad).cwiseAbs().maxCoeff() < 1e-12;
  const std::optional<JointVector> narrow =
      s.whole_body_guidance && s.narrow_shape_draws > 0 ? narrow_shape(start.base, rep) : std::nullopt;
  auto arm_blocked = [&](const BasePose& p) {
    if (!s.whole_body_guidance || s.arm_blocked_cost_factor <= 0.0) return false;
    RobotConfiguration c{p, start.q_rad};
    ++rep.collision_checks;
    if (!checker_.check(c)) return false;
    if (!same_arm) {
      c.q_rad = goal.q_rad;
      ++rep.collision_checks;
      if (!checker_.check(c)) return false;
    }
    if (!narrow) return true;
    c.q_rad = *narrow;
    ++rep.collision_checks;
    return static_cast<bool>(checker_.check(c));
  };

  std::vector<BaseSample> shot;
  auto try_shot = [&](const BasePose& from) {
    const RsPath path = rs_->shortest(from, goal.base);
    if (!std::isfinite(path.length_m) || path.cusps() > s.max_shot_cusps) return false;
    std::vector<BaseSample> fine;
    sample_rs_path(from, path, s.collision_step_m, &fine);
    if (!detail::base_samples_free(checker_, fine, &rep.collision_checks)) return false;
    shot.clear();
    sample_rs_path(from, path, s.step_length_m, &shot);
    for (std::size_t i = 1; i < shot.size(); ++i) {
      if (!detail::base_chord_free(checker_, shot[i - 1].pose, shot[i].pose, chord_reach_m_, s.collision_step_m,
                                   &rep.collision_checks))
        return false;
    }
    return true;
  };

  ++generation_;
  if (generation_ == 0) {  // wrapped: reset the stamps
    std::fill(stamp_.begin(), stamp_.end(), 0u);
    generation_ = 1;
  }
  std::vector<Node> nodes;
  nodes.reserve(4096);
  std::priority_queue<OpenItem, std::vector<OpenItem>, std::greater<OpenItem>> open;
  auto lookup = [&](std::int32_t cell) -> std::int32_t {
    return stamp_[static_cast<std::size_t>(cell)] == generation_ ? cell_node_[static_cast<std::size_t>(cell)] : -1;
  };
  auto assign = [&](std::int32_t cell, std::int32_t node) {
    stamp_[static_cast<std::size_t>(cell)] = generation_;
    cell_node_[static_cast<std::size_t>(cell)] = node;
  };

  {
    Node n0;
    n0.pose = start.base;
    n0.cell = cell_of(start.base);
    if (n0.cell < 0) return finish(planner::Status::kInvalidStart, "start outside the map");
    nodes.push_back(n0);
    assign(n0.cell, 0);
    open.push({s.heuristic_weight * heuristic(start.base), 0});
  }

  const int half = s.steering_samples / 2;
  std::int32_t found = -1;
  while (!open.empty()) {
    const OpenItem top = open.top();
    open.pop();
    Node& cur = nodes[static_cast<std::size_t>(top.node)];
    if (cur.closed || lookup(cur.cell) != top.node) continue;
    cur.closed = true;
    ++rep.iterations;
    if ((rep.iterations & 15) == 0 && deadline.expired()) return finish(planner::Status::kTimeout, "time budget exhausted");
    if (rep.iterations > s.max_expansions) return finish(planner::Status::kTimeout, "expansion cap reached");

    const BasePose cur_pose = cur.pose;
    const double cur_g = cur.g;
    const int cur_eta = cur.eta, cur_steer = cur.steer;
    const bool near_goal = grid_.distance(cur_pose.x_m, cur_pose.y_m) < s.analytic_expansion_range_m;
    if ((near_goal || rep.iterations % s.analytic_expansion_interval == 1) && try_shot(cur_pose)) {
      found = top.node;
      break;
    }

    for (int eta : {1, -1}) {
      for (int k = -half; k <= half; ++k) {
        const double kappa = static_cast<double>(k) / half / radius_m_;
        const double len = eta * s.step_length_m;
        const BasePose next = drive_arc(cur_pose, kappa, len);
        const std::int32_t cell = cell_of(next);
        if (cell < 0) continue;
        const std::int32_t existing = lookup(cell);
        if (existing >= 0 && nodes[static_cast<std::size_t>(existing)].closed) continue;
        double g = cur_g + s.step_length_m * (eta > 0 ? 1.0 : s.reverse_cost_factor) +
                   s.steering_cost * std::abs(static_cast<double>(k) / half) * s.step_length_m;
        if (cur_eta != 0 && eta != cur_eta) g += s.gear_switch_cost_m;
        if (cur_eta != 0) g += s.steering_change_cost * std::abs(k - cur_steer) / static_cast<double>(half);
        if (existing >= 0 && nodes[static_cast<std::size_t>(existing)].g <= g) continue;
        if (!detail::base_arc_free(checker_, cur_pose, kappa, len, base_reach_m_, s.collision_step_m,
                                   &rep.collision_checks))
          continue;
        if (k != 0 && !detail::base_chord_free(checker_, cur_pose, next, chord_reach_m_, s.collision_step_m,
                                               &rep.collision_checks))
          continue;  // a straight primitive's chord is its arc
        if (arm_blocked(next)) g += s.arm_blocked_cost_factor * s.step_length_m;
        if (existing >= 0 && nodes[static_cast<std::size_t>(existing)].g <= g) continue;
        const double h = heuristic(next);
        if (!std::isfinite(h)) continue;
        Node n;
        n.pose = next;
        n.g = g;
        n.parent = top.node;
        n.cell = cell;
        n.eta = static_cast<std::int8_t>(eta);
        n.steer = static_cast<std::int8_t>(k);
        const auto id = static_cast<std::int32_t>(nodes.size());
        nodes.push_back(n);
        assign(cell, id);
        open.push({g + s.heuristic_weight * h, id});
      }
    }
  }
  if (found < 0) return finish(planner::Status::kNoPath, "search space exhausted");

  std::vector<std::int32_t> chain;
  for (std::int32_t i = found; i >= 0; i = nodes[static_cast<std::size_t>(i)].parent) chain.push_back(i);
  std::reverse(chain.begin(), chain.end());
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const Node& n = nodes[static_cast<std::size_t>(chain[i])];
    result.path.push_back({n.pose, n.eta});
  }
  const bool shot_moves = shot.size() > 1 &&
                          !(shot.size() == 2 && std::hypot(shot[1].pose.x_m - shot[0].pose.x_m,
                                                           shot[1].pose.y_m - shot[0].pose.y_m) < 1e-9 &&
                            std::abs(planner::wrap_angle_rad(shot[1].pose.yaw_rad - shot[0].pose.yaw_rad)) < 1e-9);
  if (shot_moves) {
    result.path.back().eta = result.path.size() == 1 ? shot[1].eta : result.path.back().eta;
    for (std::size_t i = 1; i < shot.size(); ++i) result.path.push_back(shot[i]);
    result.analytic_expansion = true;
  } else if (result.path.size() == 1) {
    result.path.push_back({goal.base, 1});  // start == goal: a zero-length base path
  }
  if (result.path.size() > 1 && result.path.front().eta == 0) result.path.front().eta = result.path[1].eta;
  result.path.back().pose = goal.base;  // exact, removes the shot's rounding
  return finish(planner::Status::kSuccess, "");
}

}  // namespace porter::frontend
