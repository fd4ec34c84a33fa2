#pragma once
// The C^2 diffeomorphism between an unconstrained variable tau in R and a positive duration
// T in (0, inf) (GCOPTER's forwardT/backwardT):
//
//   T(tau) = tau^2/2 + tau + 1          for tau > 0
//   T(tau) = 1 / (tau^2/2 - tau + 1)    for tau <= 0
//
// T(0) = 1, dT/dtau(0) = 1 and d2T/dtau2(0) = 1 from both sides. T grows quadratically for
// large tau and decays like 2/tau^2 for very negative tau, which keeps L-BFGS steps in tau
// well scaled (exp(tau) would not). Pure functions, thread-safe.

#include <cmath>

namespace porter::minco {

/// T(tau) in seconds; always > 0 for finite tau.
inline double duration_from_tau(double tau) {
  return tau > 0.0 ? (0.5 * tau + 1.0) * tau + 1.0 : 1.0 / ((0.5 * tau - 1.0) * tau + 1.0);
}

/// Inverse map. duration_s must be > 0 (returns -inf for 0, NaN for negative input).
inline double tau_from_duration(double duration_s) {
  return duration_s > 1.0 ? std::sqrt(2.0 * duration_s - 1.0) - 1.0
                          : 1.0 - std::sqrt(2.0 / duration_s - 1.0);
}

/// dT/dtau.
inline double duration_derivative(double tau) {
  if (tau > 0.0) return tau + 1.0;
  const double den = (0.5 * tau - 1.0) * tau + 1.0;
  return (1.0 - tau) / (den * den);
}

}  // namespace porter::minco
