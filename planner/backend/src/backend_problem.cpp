#include "porter/backend/backend_problem.hpp"

#include <algorithm>
#include <cmath>
#include <limits>


namespace porter::backend {

BackendProblem::BackendProblem(midend::ReferencePath reference, const midend::MidendLimits& limits,
                               const midend::MidendSettings& settings, SafetyTerm& safety,
                               SelfCollisionTerm* self_collision)
    : midend_(std::move(reference), limits, settings), safety_(&safety), self_(self_collision) {
  midend_.set_extra_cost([this](const Trajectory& traj, midend::ExtraCostGradient* grad) {
    return safety_cost(traj, grad);
  });
}

double BackendProblem::safety_cost(const Trajectory& traj, midend::ExtraCostGradient* grad) {
  const int n = traj.num_pieces();
  tgrad_.reset(n);
  double raw = safety_->evaluate(traj, tgrad_, &stats_);
  last_js_ = raw;
  last_self_ = 0.0;
  if (self_) {
    last_self_ = self_->evaluate(traj, tgrad_, &self_stats_);
    raw += last_self_;
  }
  const double js = safety_scale_ * raw;
  if (!std::isfinite(js)) return std::numeric_limits<double>::infinity();
  if (grad) {
    if (static_cast<int>(grad->coeffs.size()) != n || static_cast<int>(grad->durations_s.size()) != n)
      return std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      grad->coeffs[k] += safety_scale_ * tgrad_.coeffs(i);
      grad->durations_s[k] += safety_scale_ * tgrad_.duration(i);
    }
  }
  return js;
}

std::optional<Trajectory> BackendProblem::trajectory(const double* x) {
  std::vector<TrajectoryPiece> pieces = midend_.pieces(x);
  if (pieces.empty()) return std::nullopt;
  TrajectoryResult r = Trajectory::create(std::move(pieces), midend_.start_yaw_rad());
  return std::move(r.trajectory);
}

double BackendProblem::evaluate(const double* x, double* grad, BackendCost* cost, double cutoff) {
  BackendCost local;
  BackendCost& c = cost ? *cost : local;
  c = BackendCost{};
  stats_ = SafetyStats{};
  self_stats_ = SelfCollisionStats{};
  last_self_ = 0.0;
  last_js_ = 0.0;
  midend_.set_extra_cutoff(cutoff);
  const double f = midend_.evaluate(x, grad, &c.midend);
  c.safety_skipped = midend_.extra_skipped();
  c.self_collision = last_self_;
  c.safety = last_js_;
  c.safety_stats = stats_;
  c.self_stats = self_stats_;
  if (!std::isfinite(f)) {
    if (grad) std::fill(grad, grad + num_variables(), 0.0);
    return std::numeric_limits<double>::infinity();
  }
  return f;
}

}  // namespace porter::backend
