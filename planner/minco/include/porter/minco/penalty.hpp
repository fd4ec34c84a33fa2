#pragma once
// One-sided penalty functions for constraint transcription: phi(x) = 0 for x <= 0 (constraint
// satisfied), growing for x > 0 (violation). Both are C^2 at 0. Pure, thread-safe.
//
//   smoothed L1 (GCOPTER): (mu - x/2)(x/mu)^3 on [0, mu], x - mu/2 above; slope 1 for x > mu,
//                          so the penalty weight is the price per unit of violation.
//   cubic (REMANI)       : x^3.

namespace porter::minco {

enum class PenaltyKind { kSmoothedL1, kCubic };

inline const char* to_string(PenaltyKind kind) {
  return kind == PenaltyKind::kSmoothedL1 ? "smoothed_l1" : "cubic";
}

/// Smoothed L1 with smoothing width mu > 0. Writes dphi/dx to *grad.
inline double smoothed_l1(double x, double mu, double* grad) {
  if (x <= 0.0) {
    *grad = 0.0;
    return 0.0;
  }
  if (x < mu) {
    const double r = x / mu;
    *grad = r * r * (3.0 - 2.0 * r);
    return (mu - 0.5 * x) * r * r * r;
  }
  *grad = 1.0;
  return x - 0.5 * mu;
}

inline double cubic_penalty(double x, double* grad) {
  if (x <= 0.0) {
    *grad = 0.0;
    return 0.0;
  }
  *grad = 3.0 * x * x;
  return x * x * x;
}

/// A penalty choice with its parameter; value() dispatches.
struct PenaltyFunction {
  PenaltyKind kind = PenaltyKind::kSmoothedL1;
  double mu = 1e-2;  ///< smoothing width of kSmoothedL1, in the units of x; ignored by kCubic

  double value(double x, double* grad) const {
    return kind == PenaltyKind::kSmoothedL1 ? smoothed_l1(x, mu, grad) : cubic_penalty(x, grad);
  }
};

}  // namespace porter::minco
