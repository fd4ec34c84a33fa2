#pragma once
// Internal: which reference node a penalty sample's pose residual uses (paper eq. pose_residual:
// the front-end node nearest in time). A piece spans m >= 1 reference edges whose nodes lie at
// fixed fractions f[0] = 0 < f[1] < ... < f[m] = 1 of its duration (reference_path.hpp, step 8);
// sample j of kappa lies at fraction j / kappa. Exactly midway between two nodes both are
// nearest and each counts at half weight (for m = 1 this is the sample j = kappa / 2).
// Pure; thread-safe.

namespace porter::midend::detail {

/// Advances *k (start at 0; samples must be visited in increasing j) to the piece-local index
/// of the node nearest to sample j; *tie is true when nodes *k and *k + 1 are equally near.
/// The comparison 2 j vs kappa (f_k + f_k+1) is exact for f = {0, 1}.
inline void nearest_node(const double* f, int m, int j, int kappa, int* k, bool* tie) {
  while (*k < m && 2.0 * j > kappa * (f[*k] + f[*k + 1])) ++*k;
  *tie = *k < m && 2.0 * j == kappa * (f[*k] + f[*k + 1]);
}

}  // namespace porter::midend::detail
