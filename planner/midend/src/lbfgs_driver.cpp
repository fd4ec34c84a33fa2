#include "porter/midend/lbfgs_driver.hpp"

#include <algorithm>

namespace porter::midend {

namespace {
/// What an evaluation reports once the deadline has expired inside a line search.
constexpr double kExpiredCost = 1e300;
}  // namespace

int to_lbfgs_line_search(LineSearch ls) {
  switch (ls) {
    case LineSearch::kMoreThuente: return LBFGS_LINESEARCH_MORETHUENTE;
    case LineSearch::kBacktrackingWolfe: return LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
    case LineSearch::kBacktrackingStrongWolfe: return LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
    case LineSearch::kBacktrackingArmijo: return LBFGS_LINESEARCH_BACKTRACKING_ARMIJO;
  }
  return LBFGS_LINESEARCH_DEFAULT;
}

LbfgsDriver::LbfgsDriver(int n) : n_(n), y_(n > 0 ? lbfgs_malloc(n) : nullptr), x_(n > 0 ? n : 0) {}

LbfgsDriver::~LbfgsDriver() { lbfgs_free(y_); }

void LbfgsDriver::set_x(const Eigen::VectorXd& x, double scale) {
  scale_ = scale;
  for (int k = 0; k < n_; ++k) y_[k] = x[k] / scale;
}

Eigen::VectorXd LbfgsDriver::x() const {
  Eigen::VectorXd x(n_);
  for (int k = 0; k < n_; ++k) x[k] = scale_ * y_[k];
  return x;
}

lbfgsfloatval_t LbfgsDriver::evaluate_cb(void* instance, const lbfgsfloatval_t* y, lbfgsfloatval_t* g, int n,
                                         lbfgsfloatval_t /*step*/) {
  auto* d = static_cast<LbfgsDriver*>(instance);
  if (d->stop_in_line_search_ && d->evaluations_ > 0 && !d->expired_ && d->deadline_->expired()) d->expired_ = true;
  if (d->expired_) {
    if (g) std::fill(g, g + n, 0.0);
    return kExpiredCost;
  }
  ++d->evaluations_;
  for (int k = 0; k < n; ++k) d->x_[k] = d->scale_ * y[k];
  const double f = (*d->objective_)(d->x_.data(), g);
  if (g) {
    for (int k = 0; k < n; ++k) g[k] *= d->scale_;
  }
  return f;
}

int LbfgsDriver::progress_cb(void* instance, const lbfgsfloatval_t* y, const lbfgsfloatval_t* /*g*/,
                             lbfgsfloatval_t fx, lbfgsfloatval_t /*xnorm*/, lbfgsfloatval_t /*gnorm*/,
                             lbfgsfloatval_t /*step*/, int n, int k, int /*ls*/) {
  auto* d = static_cast<LbfgsDriver*>(instance);
  d->run_.iterations = k;
  // Any non-zero value ends lbfgs(), which returns it verbatim; not 1 (LBFGS_STOP, the relative
  // cost test's own code), so a stop here is never mistaken for convergence.
  constexpr int kStop = LBFGSERR_CANCELED;
  if (d->monitor_ && *d->monitor_) {
    for (int i = 0; i < n; ++i) d->x_[i] = d->scale_ * y[i];
    if (!(*d->monitor_)(d->x_.data(), fx, k)) {
      d->run_.stop = LbfgsStop::kRequested;
      return kStop;
    }
  }
  if (d->deadline_->expired()) {
    d->run_.stop = d->deadline_->canceled() ? LbfgsStop::kCanceled : LbfgsStop::kDeadline;
    return kStop;
  }
  return 0;
}

LbfgsDriver::Run LbfgsDriver::run(const lbfgs_parameter_t& param, const Objective& objective, const Monitor& monitor,
                                  const planner::Deadline& deadline) {
  run_ = Run{};
  objective_ = &objective;
  monitor_ = &monitor;
  deadline_ = &deadline;
  lbfgs_parameter_t p = param;
  lbfgsfloatval_t fx = 0.0;
  run_.code = lbfgs(n_, y_, &fx, evaluate_cb, progress_cb, this, &p);
  run_.f = fx;
  objective_ = nullptr;
  monitor_ = nullptr;
  deadline_ = nullptr;
  return run_;
}

}  // namespace porter::midend
