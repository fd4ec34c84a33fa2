#include "frontend_test_utils.hpp"
#include "porter/planner/angle.hpp"

#include <sstream>

namespace porter::test {

bool same_config(const RobotConfiguration& a, const RobotConfiguration& b, double tol) {
  return std::abs(a.base.x_m - b.base.x_m) <= tol && std::abs(a.base.y_m - b.base.y_m) <= tol &&
         std::abs(planner::wrap_angle_rad(a.base.yaw_rad - b.base.yaw_rad)) <= tol &&
         (a.q_rad - b.q_rad).cwiseAbs().maxCoeff() <= tol;
}

std::vector<FlatNode> flatten(const planner::WholeBodyPath& path) {
  std::vector<FlatNode> out;
  for (std::size_t s = 0; s < path.segments.size(); ++s) {
    const auto& seg = path.segments[s];
    for (std::size_t i = 0; i < seg.nodes.size(); ++i) {
      if (s > 0 && i == 0) continue;  // shared with the previous segment
      out.push_back({seg.nodes[i], seg.eta});
    }
  }
  if (out.size() > 1) out.front().eta = out[1].eta;
  return out;
}

std::vector<std::string> check_path(const planner::WholeBodyPath& path, const RobotModel& model,
                                    const std::vector<const planner::CollisionChecker*>& checkers,
                                    const PathCheckOptions& opt) {
  std::vector<std::string> errors;
  auto err = [&](const std::string& what, std::size_t i) {
    std::ostringstream os;
    os << what << " (node " << i << ")";
    if (errors.size() < 20) errors.push_back(os.str());
  };
  if (path.segments.empty()) {
    errors.push_back("no segments");
    return errors;
  }
  for (std::size_t s = 0; s < path.segments.size(); ++s) {
    const auto& seg = path.segments[s];
    if (seg.eta != 1 && seg.eta != -1) err("segment eta not +-1", s);
    if (seg.nodes.size() < 2 && path.segments.size() > 1) err("segment with fewer than 2 nodes", s);
    if (s > 0) {
      const auto& prev = path.segments[s - 1];
      if (prev.eta == seg.eta) err("consecutive segments with the same eta", s);
      if (!same_config(prev.nodes.back().config, seg.nodes.front().config, 0.0) ||
          prev.nodes.back().time_s != seg.nodes.front().time_s)
        err("gear-switch node not shared", s);
    }
  }
  const std::vector<FlatNode> nodes = flatten(path);
  if (opt.start && !same_config(nodes.front().node.config, *opt.start)) err("first node is not the start", 0);
  if (opt.goal && !same_config(nodes.back().node.config, *opt.goal, 1e-6)) err("last node is not the goal", nodes.size() - 1);
  if (nodes.front().node.time_s != 0.0) err("path does not start at t = 0", 0);
  const JointVector vmax = model.velocity_limits();
  const double R = opt.turning_radius_m;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const RobotConfiguration& c = nodes[i].node.config;
    if (!model.within_joint_limits(c.q_rad, 1e-9)) err("joint limits violated", i);
    for (const auto* checker : checkers)
      if (checker->check(c)) err("node in collision for checker " + checker->name(), i);
    if (i == 0) continue;
    const RobotConfiguration& p = nodes[i - 1].node.config;
    const double dt = nodes[i].node.time_s - nodes[i - 1].node.time_s;
    if (!(dt > 0.0)) err("time does not increase", i);
    if (((c.q_rad - p.q_rad).cwiseAbs().array() > vmax.array() * dt * (1.0 + 1e-9)).any())
      err("joint speed limit violated", i);
    const double dx = c.base.x_m - p.base.x_m, dy = c.base.y_m - p.base.y_m;
    const double chord = std::hypot(dx, dy);
    const double dyaw = planner::wrap_angle_rad(c.base.yaw_rad - p.base.yaw_rad);
    if (chord < 1e-9) {
      if (std::abs(dyaw) > 1e-9) err("turn in place", i);
    } else {
      if (std::abs(dyaw) > 2.0 * std::asin(std::min(1.0, chord / (2.0 * R))) + 1e-6) err("turning radius violated", i);
      const double heading = std::atan2(dy, dx) + (nodes[i].eta < 0 ? M_PI : 0.0);
      if (std::abs(planner::wrap_angle_rad(heading - (p.base.yaw_rad + 0.5 * dyaw))) > 1e-6)
        err("yaw not tied to the driving direction", i);
    }
    for (const auto* checker : checkers)
      if (checker->check_motion(p, c)) err("edge in collision for checker " + checker->name(), i);
  }
  return errors;
}

}  // namespace porter::test
