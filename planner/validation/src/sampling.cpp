// Sample times such that no point of the robot moves more than max_step_m between neighbours.
#include <algorithm>
#include <cmath>

#include "porter/validation/validator.hpp"

namespace porter::validation {
namespace {

struct BodySphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< body frame
  double radius_m = 0.0;
  bool present = false;
};

std::array<BodySphere, kNumBodies> body_spheres(const RobotModel& model, const Payload& payload) {
  std::array<BodySphere, kNumBodies> out;
  for (int b = 0; b < kNumBodies; ++b) {
    std::vector<CollisionShape> shapes;
    if (b == kPayloadBody) {
      for (CollisionShape s : payload.shapes) {
        s.T_parent_shape = payload.T_EE_P * s.T_parent_shape;
        shapes.push_back(s);
      }
    } else {
      shapes = model.links[static_cast<size_t>(b)].shapes;
    }
    if (shapes.empty()) continue;
    Eigen::AlignedBox3d box;
    for (const CollisionShape& s : shapes) box.extend(shape_bounds(s));
    BodySphere& sphere = out[static_cast<size_t>(b)];
    sphere.center = box.center();
    for (const CollisionShape& s : shapes)
      sphere.radius_m = std::max(sphere.radius_m, shape_max_distance(s, sphere.center));
    sphere.present = true;
  }
  return out;
}

// Largest displacement of any point of any body between two pose sets: for a rigid body whose
// points lie within r of c, |p1 - p0| <= |c1 - c0| + 2 r sin(theta / 2) <= |c1 - c0| + r theta.
double displacement_bound(const std::array<BodySphere, kNumBodies>& spheres, const BodyPoses& a,
                          const BodyPoses& b) {
  double worst = 0.0;
  for (int k = 0; k < kNumBodies; ++k) {
    const BodySphere& s = spheres[static_cast<size_t>(k)];
    if (!s.present) continue;
    const Eigen::Isometry3d& Ta = a[static_cast<size_t>(k)];
    const Eigen::Isometry3d& Tb = b[static_cast<size_t>(k)];
    const double dc = (Tb * s.center - Ta * s.center).norm();
    const Eigen::AngleAxisd rel(Ta.linear().transpose() * Tb.linear());
    worst = std::max(worst, dc + s.radius_m * std::abs(rel.angle()));
  }
  return worst;
}

}  // namespace

WholeBodyConfig config_at(const FlatTrajectory& trajectory, double t_s) {
  const FlatVector z = trajectory.derivative(t_s, 0);
  WholeBodyConfig c;
  c.x_m = z[0];
  c.y_m = z[1];
  c.yaw_rad = trajectory.yaw_rad(t_s);
  c.q_rad = z.tail<kNumArmJoints>();
  return c;
}

std::vector<double> sample_times(const RobotModel& model, const Payload& payload,
                                 const FlatTrajectory& trajectory, const ValidationSettings& settings,
                                 double* max_step_m) {
  const auto spheres = body_spheres(model, payload);
  const double step_m = settings.max_step_m > 0.0 ? settings.max_step_m : 0.01;
  const double dt_max = settings.max_dt_s > 0.0 ? settings.max_dt_s : 0.02;
  constexpr double kMinDt = 1e-7;  // a pose jump (not a motion) stops the bisection here

  // Coarse grid: every piece boundary, at most dt_max apart.
  std::vector<double> coarse;
  for (int i = 0; i < trajectory.num_pieces(); ++i) {
    const double t0 = trajectory.piece_start_s(i), T = trajectory.piece(i).duration_s;
    const int n = std::max(1, static_cast<int>(std::ceil(T / dt_max)));
    for (int k = 0; k < n; ++k) coarse.push_back(t0 + T * k / n);
  }
  coarse.push_back(trajectory.duration_s());

  std::vector<double> times{coarse.front()};
  double worst = 0.0;
  BodyPoses prev = body_poses(model, config_at(trajectory, coarse.front()));
  for (size_t i = 1; i < coarse.size(); ++i) {
    // Depth-first bisection of [times.back(), coarse[i]].
    std::vector<std::pair<double, BodyPoses>> stack;
    stack.emplace_back(coarse[i], body_poses(model, config_at(trajectory, coarse[i])));
    while (!stack.empty()) {
      const double t0 = times.back();
      const auto& [t1, P1] = stack.back();
      const double d = displacement_bound(spheres, prev, P1);
      if (d > step_m && t1 - t0 > kMinDt) {
        const double tm = 0.5 * (t0 + t1);
        BodyPoses Pm = body_poses(model, config_at(trajectory, tm));
        stack.emplace_back(tm, Pm);
        continue;
      }
      worst = std::max(worst, d);
      times.push_back(t1);
      prev = P1;
      stack.pop_back();
    }
  }
  if (max_step_m) *max_step_m = worst;
  return times;
}

}  // namespace porter::validation
