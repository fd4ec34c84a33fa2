#pragma once
// The sphere baseline's back-end collision term (REMANI / TOPAY style, algorithms.md §2.2, §2.4):
// the time integral, over every piece, of a cubic penalty on each robot sphere's clearance,
//   J = w * int sum_spheres L(max(0, s_thr - (ESDF(c(t)) - r))) dt  (+ the same against the ground
//   for links >= 1, with z - r in place of the ESDF),
// transcribed with kappa + 1 trapezoid samples per piece like the mid-end's penalties
// (minco/penalty_integral.hpp: the same weights and duration terms). Gradients through the sphere
// centres' point Jacobians and the heading rule (backend/trajectory_gradient.hpp).
//
// prepare() builds the ESDF over the warm start's swept boxes plus crop_margin_m.
// Thread-safety: one instance per solve.

#include <string>

#include "porter/backend/safety_term.hpp"
#include "porter/backend/swept_body.hpp"
#include "porter/baselines/distance_field.hpp"
#include "porter/baselines/sphere_cover.hpp"

namespace porter::baselines {

struct SphereSafetySettings {
  SphereCoverSettings cover;
  /// s_thr on top of each sphere's radius, m. > 0.
  double safety_margin_m = 0.1;
  /// w: cost per m^3 of violation per second. > 0.
  double weight = 1e5;
  /// kappa: trapezoid intervals per piece. >= 1.
  int samples_per_piece = 16;
  /// ESDF region: the warm start's swept boxes padded by this, m.
  double crop_margin_m = 1.0;
  /// ESDF clamp, m (> s_thr + radius).
  double max_distance_m = 0.5;
  backend::SweptBodySettings body;
};

class SphereSafetyTerm final : public backend::SafetyTerm {
 public:
  SphereSafetyTerm(const RobotModel& model, const SphereSafetySettings& settings = {});

  void prepare(const OccupancyGrid& map_W, const Trajectory& initial) override;
  double evaluate(const Trajectory& trajectory, backend::TrajectoryGradient& grad,
                  backend::SafetyStats* stats) override;
  std::string name() const override { return "spheres"; }

  const RobotSpheres& spheres() const { return spheres_; }
  const DistanceField& field() const { return field_; }

 private:
  SphereSafetySettings settings_;
  RobotSpheres spheres_;
  backend::SweptBody body_;
  DistanceField field_;
  backend::BodyState state_;
};

}  // namespace porter::baselines
