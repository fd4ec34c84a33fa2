#pragma once
// The one L-BFGS driver of the planner's optimizers (mid-end and back-end): liblbfgs (Debian's
// liblbfgs-dev) on scaled variables y = x / scale, with the time budget and cancellation of a
// planner::Deadline, a per-iteration monitor that may stop the run, and the parameter block built
// from a stage's settings.
//
//   LbfgsDriver driver(n);
//   driver.set_x(x0, settings.variable_scale);
//   LbfgsDriver::Run run = driver.run(lbfgs_parameters(settings), objective, monitor, deadline);
//   x = driver.x();
//
// The objective sees the unscaled x and returns the gradient with respect to x; the driver does
// the chain rule for the scale. A run ends when liblbfgs stops by itself (its code says why), when
// the monitor returns false (LbfgsStop::kRequested), or when the deadline expires: checked after
// every iteration (kDeadline, or kCanceled when its flag was set) and, with
// set_stop_in_line_search(true), before every evaluation once the driver has made one: an expired
// evaluation reports a huge cost with a zero gradient, so the line search cannot accept a step and
// liblbfgs returns its last accepted iterate (an iteration can be long when each evaluation costs
// milliseconds; the back-end uses this, the mid-end does not).
//
// Thread-safety: one driver per solve; run() calls the objective and monitor on its own thread.

#include <lbfgs.h>

#include <functional>

#include <Eigen/Core>

#include "porter/midend/midend_settings.hpp"
#include "porter/planner/deadline.hpp"

namespace porter::midend {

/// liblbfgs's constant for our line-search choice.
int to_lbfgs_line_search(LineSearch ls);

/// lbfgs_parameter_t for a settings struct with the solver fields memory_size,
/// relative_cost_past, relative_cost_tolerance, max_iterations, line_search and max_line_search.
/// The gradient-norm test is off: both stages stop on relative cost decrease only, because their
/// penalties are nonsmooth.
template <class Settings>
lbfgs_parameter_t lbfgs_parameters(const Settings& s) {
  lbfgs_parameter_t param;
  lbfgs_parameter_init(&param);
  param.m = s.memory_size;
  param.epsilon = 0.0;
  param.past = s.relative_cost_past;
  param.delta = s.relative_cost_tolerance;
  param.max_iterations = s.max_iterations;
  param.linesearch = to_lbfgs_line_search(s.line_search);
  param.max_linesearch = s.max_line_search;
  return param;
}

/// Why the driver (not liblbfgs) ended a run.
enum class LbfgsStop {
  kNone,       ///< liblbfgs stopped by itself (converged, stalled, iteration cap, error)
  kDeadline,   ///< the deadline's time ran out
  kCanceled,   ///< the deadline's cancellation flag was set
  kRequested,  ///< the monitor returned false
};

class LbfgsDriver {
 public:
  /// Cost at x (unscaled, size n); when grad is non-null, writes d cost / d x there. Must not throw.
  using Objective = std::function<double(const double* x, double* grad)>;
  /// Called after each accepted iterate with x (unscaled), its cost and the run's iteration count
  /// k >= 1; returning false ends the run. May be empty.
  using Monitor = std::function<bool(const double* x, double f, int k)>;

  struct Run {
    int code = 0;        ///< lbfgs()'s return code (LBFGSERR_CANCELED when the driver ended it)
    int iterations = 0;  ///< iterations of this run
    double f = 0.0;      ///< cost at the point left in the driver
    LbfgsStop stop = LbfgsStop::kNone;
  };

  /// n >= 1 variables; ok() is false when liblbfgs could not allocate them.
  explicit LbfgsDriver(int n);
  ~LbfgsDriver();
  LbfgsDriver(const LbfgsDriver&) = delete;
  LbfgsDriver& operator=(const LbfgsDriver&) = delete;

  bool ok() const { return y_ != nullptr; }
  int size() const { return n_; }
  double scale() const { return scale_; }

  /// Sets the point (y = x / scale), scale > 0.
  void set_x(const Eigen::VectorXd& x, double scale);
  /// The current point, unscaled (scale * y).
  Eigen::VectorXd x() const;

  /// See the header comment.
  void set_stop_in_line_search(bool on) { stop_in_line_search_ = on; }
  /// An evaluation was refused because the deadline had expired (set_stop_in_line_search).
  bool expired_in_line_search() const { return expired_; }
  /// Objective calls over every run.
  int evaluations() const { return evaluations_; }

  /// One liblbfgs run from the current point; leaves the point liblbfgs returns.
  Run run(const lbfgs_parameter_t& param, const Objective& objective, const Monitor& monitor,
          const planner::Deadline& deadline);

 private:
  static lbfgsfloatval_t evaluate_cb(void* instance, const lbfgsfloatval_t* y, lbfgsfloatval_t* g, int n,
                                     lbfgsfloatval_t step);
  static int progress_cb(void* instance, const lbfgsfloatval_t* y, const lbfgsfloatval_t* g, lbfgsfloatval_t fx,
                         lbfgsfloatval_t xnorm, lbfgsfloatval_t gnorm, lbfgsfloatval_t step, int n, int k, int ls);

  int n_ = 0;
  lbfgsfloatval_t* y_ = nullptr;
  double scale_ = 1.0;
  Eigen::VectorXd x_;  ///< scratch: the unscaled point handed to the callbacks
  bool stop_in_line_search_ = false;
  bool expired_ = false;
  int evaluations_ = 0;
  // Per run.
  const Objective* objective_ = nullptr;
  const Monitor* monitor_ = nullptr;
  const planner::Deadline* deadline_ = nullptr;
  Run run_;
};

}  // namespace porter::midend
