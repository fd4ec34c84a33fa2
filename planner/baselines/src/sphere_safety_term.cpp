#include "porter/baselines/sphere_safety_term.hpp"

#include <chrono>

namespace porter::baselines {

SphereSafetyTerm::SphereSafetyTerm(const RobotModel& model, const SphereSafetySettings& settings)
    : settings_(settings), spheres_(cover_robot(model, settings.cover)), body_(model, settings.body) {}

void SphereSafetyTerm::prepare(const OccupancyGrid& map_W, const Trajectory& initial) {
  body_.reset(initial);
  Eigen::AlignedBox3d region;
  for (int j = 0; j < kNumLinks; ++j) region.extend(body_.link_box(j));
  region.min().array() -= settings_.crop_margin_m;
  region.max().array() += settings_.crop_margin_m;
  field_ = DistanceField::build(map_W, region, settings_.max_distance_m);
}

double SphereSafetyTerm::evaluate(const Trajectory& traj, backend::TrajectoryGradient& grad,
                                  backend::SafetyStats* stats) {
  const auto start = std::chrono::steady_clock::now();
  body_.reset(traj);
  backend::SafetyStats local;
  const double s_thr = settings_.safety_margin_m;
  const double w = settings_.weight;
  const int kappa = settings_.samples_per_piece;
  for (const LinkSpheres& s : spheres_) local.obstacle_points += static_cast<int>(s.centers_L.size());
  double total = 0.0;
  for (int i = 0; i < traj.num_pieces(); ++i) {
    const TrajectoryPiece& piece = traj.piece(i);
    const double h = piece.duration_s / kappa;
    for (int k = 0; k <= kappa; ++k) {
      const double frac = static_cast<double>(k) / kappa;
      const double tau = frac * piece.duration_s;
      body_.evaluate_piece(i, tau, state_);
      double G = 0.0;
      DofVector d_config = DofVector::Zero();
      for (int l = 0; l < kNumLinks; ++l) {
        const LinkSpheres& s = spheres_[static_cast<std::size_t>(l)];
        const auto lu = static_cast<std::size_t>(l);
        for (const Eigen::Vector3d& c_L : s.centers_L) {
          const Eigen::Vector3d c = state_.kin.R_W_L[lu] * c_L + state_.kin.t_W_L[lu];
          Eigen::Vector3d grad_c;
          const double d = field_.distance(c, &grad_c) - s.radius_m;
          ++local.link_queries;
          local.min_distance_m = std::min(local.min_distance_m, d);
          Eigen::Vector3d dG = Eigen::Vector3d::Zero();
          if (s_thr - d > 0.0) {
            const double x = s_thr - d;
            ++local.violations;
            local.inside += d < 0.0;
            G += w * x * x * x;
            dG += -3.0 * w * x * x * grad_c;
          }
          if (l >= 1 && s_thr - (c.z() - s.radius_m) > 0.0) {  // the ground
            const double x = s_thr - (c.z() - s.radius_m);
            G += w * x * x * x;
            dG.z() += -3.0 * w * x * x;
          }
          if (dG.isZero()) continue;
          PointJacobian J;
          backend::ChainKinematics::point_jacobian(state_.kin, l, c, J);
          d_config += J.transpose() * dG;
        }
      }
      if (G == 0.0 && d_config.isZero()) continue;
      const double weight = (k == 0 || k == kappa) ? 0.5 : 1.0;
      total += weight * h * G;
      TrajVector d_z, d_heading;
      body_.config_to_flat(state_, d_config, d_z, d_heading);
      grad.add_local(i, tau, d_z, state_.heading_order, d_heading, weight * h);
      const TrajVector zdot = piece_derivative(piece.coeffs, tau, 1);
      const TrajVector zk1 = piece_derivative(piece.coeffs, tau, state_.heading_order + 1);
      grad.add_duration(i, weight * (G / kappa + h * frac * (d_z.dot(zdot) + d_heading.dot(zk1))));
    }
  }
  local.cost = total;
  local.time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (stats) *stats = local;
  return total;
}

}  // namespace porter::baselines
