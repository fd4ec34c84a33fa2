#pragma once
// Internal: passes 1 and 2 of the fast penalty kernel (piece_sampler.hpp): all samples of a
// piece evaluated as rows over the samples, and the screen that proves most of them feasible.
// Pure apart from the workspace; thread-safe with one workspace per thread.

#include "piece_sampler.hpp"

namespace porter::midend::detail {

/// Screening slack on the normalized violations: the screen recomputes the exact path's
/// expressions (or conservative forms of them), so it only absorbs rounding.
inline constexpr double kScreenSlack = 1e-9;
/// Bound on |z^(k)| below which the screen's products are exact enough (SampleRows::moderate).
inline constexpr double kScreenMagnitude = 1e100;

/// The piece's samples as rows over j (structure of arrays, so that the loops below run over
/// contiguous samples and the compiler vectorises them): local times, the 8 outputs' position,
/// velocity and acceleration, the base's jerk, and the screening result.
struct SampleRows {
  double *t, *pos, *vel, *acc, *jerk_xy;  ///< row d of pos is pos + d * n, n = kappa + 1
  double* screen;   ///< screen_samples()
  /// Every value in the rows is finite and below kScreenMagnitude in size, so that the screen's
  /// products cannot overflow (else every sample takes the exact path).
  bool moderate = false;
};

/// Pass 1: polynomial evaluation for all samples at once with the reference's Horner
/// expressions (bit for bit), one output dimension and one derivative at a time. `work` holds
/// sampler_work_size(kappa) doubles.
SampleRows evaluate_samples(const double* coeffs, double duration_s, int kappa, double* work);

/// Pass 2: writes to rows.screen[j] an upper bound (up to rounding, hence kScreenSlack) of the
/// largest normalized violation x over the sampled terms at sample j, computed with the
/// expressions of the exact path (wheels(), joints(), residual() in piece_sampler.cpp): a sample
/// whose screen is <= -kScreenSlack has x <= 0 in every term, i.e. zero value and zero partials.
/// Samples exactly midway between two reference nodes (two residual nodes) get +1.
void screen_samples(const SamplerConstants& k, const PieceInputs& in, const SampleRows& rows,
                    int kappa, bool min_speed, double inv_vmin2, bool wheels_on, bool joints_on,
                    bool residual_on);

}  // namespace porter::midend::detail
