#include "porter/minco/banded_system.hpp"

#include <algorithm>
#include <cmath>

namespace porter::minco {

void BandedSystem::resize(int n, int lower, int upper) {
  assert(n >= 0 && lower >= 0 && upper >= 0);
  n_ = n;
  lower_ = lower;
  upper_ = upper;
  width_ = lower + upper + 1;
  data_.assign(static_cast<std::size_t>(n) * width_, 0.0);
}

void BandedSystem::set_zero() { std::fill(data_.begin(), data_.end(), 0.0); }

bool BandedSystem::factorize_lu() {
  for (int k = 0; k < n_; ++k) {
    const double pivot = (*this)(k, k);
    if (pivot == 0.0 || !std::isfinite(pivot)) return false;
    const int i_end = std::min(k + lower_, n_ - 1);
    const int j_end = std::min(k + upper_, n_ - 1);
    const double* row_k = &data_[static_cast<std::size_t>(k) * width_ + lower_];  // (k, k)
    for (int i = k + 1; i <= i_end; ++i) {
      double& a_ik = (*this)(i, k);
      if (a_ik == 0.0) continue;  // structural zeros are common in the MINCO band
      const double l = a_ik / pivot;
      a_ik = l;
      double* row_i = &data_[static_cast<std::size_t>(i) * width_ + (k - i + lower_)];  // (i, k)
      for (int j = 1; j <= j_end - k; ++j) row_i[j] -= l * row_k[j];
    }
  }
  return true;
}

namespace {

// KCols > 0 fixes the number of right-hand sides at compile time (vectorized inner loops);
// KCols = 0 uses the runtime count.
template <int KCols>
void solve_impl(const BandedSystem& m, double* b, int cols_rt, int ld) {
  const int cols = KCols > 0 ? KCols : cols_rt;
  const int n = m.size(), lower = m.lower(), upper = m.upper();
  for (int i = 0; i < n; ++i) {  // L y = b (unit lower)
    double* bi = b + static_cast<std::size_t>(i) * ld;
    for (int j = std::max(0, i - lower); j < i; ++j) {
      const double l = m(i, j);
      if (l == 0.0) continue;
      const double* bj = b + static_cast<std::size_t>(j) * ld;
      for (int c = 0; c < cols; ++c) bi[c] -= l * bj[c];
    }
  }
  for (int i = n - 1; i >= 0; --i) {  // U x = y
    double* bi = b + static_cast<std::size_t>(i) * ld;
    const int j_end = std::min(i + upper, n - 1);
    for (int j = i + 1; j <= j_end; ++j) {
      const double u = m(i, j);
      if (u == 0.0) continue;
      const double* bj = b + static_cast<std::size_t>(j) * ld;
      for (int c = 0; c < cols; ++c) bi[c] -= u * bj[c];
    }
    const double inv = 1.0 / m(i, i);
    for (int c = 0; c < cols; ++c) bi[c] *= inv;
  }
}

template <int KCols>
void solve_adjoint_impl(const BandedSystem& m, double* b, int cols_rt, int ld) {
  const int cols = KCols > 0 ? KCols : cols_rt;
  const int n = m.size(), lower = m.lower(), upper = m.upper();
  for (int i = 0; i < n; ++i) {  // M^T = U^T L^T; U^T y = b (lower, non-unit)
    double* bi = b + static_cast<std::size_t>(i) * ld;
    for (int j = std::max(0, i - upper); j < i; ++j) {
      const double u = m(j, i);
      if (u == 0.0) continue;
      const double* bj = b + static_cast<std::size_t>(j) * ld;
      for (int c = 0; c < cols; ++c) bi[c] -= u * bj[c];
    }
    const double inv = 1.0 / m(i, i);
    for (int c = 0; c < cols; ++c) bi[c] *= inv;
  }
  for (int i = n - 1; i >= 0; --i) {  // L^T x = y (unit upper)
    double* bi = b + static_cast<std::size_t>(i) * ld;
    const int j_end = std::min(i + lower, n - 1);
    for (int j = i + 1; j <= j_end; ++j) {
      const double l = m(j, i);
      if (l == 0.0) continue;
      const double* bj = b + static_cast<std::size_t>(j) * ld;
      for (int c = 0; c < cols; ++c) bi[c] -= l * bj[c];
    }
  }
}

}  // namespace

void BandedSystem::solve(double* b, int cols, int ld) const {
  if (cols == 8) return solve_impl<8>(*this, b, cols, ld);
  if (cols == 1) return solve_impl<1>(*this, b, cols, ld);
  solve_impl<0>(*this, b, cols, ld);
}

void BandedSystem::solve_adjoint(double* b, int cols, int ld) const {
  if (cols == 8) return solve_adjoint_impl<8>(*this, b, cols, ld);
  if (cols == 1) return solve_adjoint_impl<1>(*this, b, cols, ld);
  solve_adjoint_impl<0>(*this, b, cols, ld);
}

}  // namespace porter::minco
