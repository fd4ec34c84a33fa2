#pragma once
// A square banded linear system M x = b with an in-place LU factorization without pivoting,
// as used by MINCO (GCOPTER's BandedSystem): M is n x n with `lower` sub-diagonals and `upper`
// super-diagonals; the factorization and each solve cost O(n * lower * upper) and
// O(n * (lower + upper) * cols).
//
// Storage is row-major over the band: entry (i, j) with -lower <= j - i <= upper lives at
// data[i * (lower + upper + 1) + (j - i + lower)], so a pivot row's band is contiguous.
//
// No pivoting: the caller guarantees that the leading principal minors are non-singular (true
// for the MINCO row ordering). factorize_lu() reports a zero or non-finite pivot by returning
// false; solves after a failed factorization produce garbage, never UB.
//
// Not thread-safe; one instance per thread. Allocates only in resize().

#include <cassert>
#include <vector>

namespace porter::minco {

class BandedSystem {
 public:
  BandedSystem() = default;
  BandedSystem(int n, int lower, int upper) { resize(n, lower, upper); }

  /// Sets the shape and zeroes every entry (reuses capacity).
  void resize(int n, int lower, int upper);
  /// Zeroes every entry, keeps the shape.
  void set_zero();

  int size() const { return n_; }
  int lower() const { return lower_; }
  int upper() const { return upper_; }

  /// Entry (i, j); only valid inside the band.
  double& operator()(int i, int j) {
    assert(i >= 0 && i < n_ && j - i >= -lower_ && j - i <= upper_);
    return data_[static_cast<std::size_t>(i) * width_ + (j - i + lower_)];
  }
  double operator()(int i, int j) const {
    assert(i >= 0 && i < n_ && j - i >= -lower_ && j - i <= upper_);
    return data_[static_cast<std::size_t>(i) * width_ + (j - i + lower_)];
  }

  /// In-place Doolittle LU (unit lower L below the diagonal, U on and above). Returns false on
  /// a zero or non-finite pivot.
  bool factorize_lu();

  /// Solves M X = B in place; B is n x cols, row-major with leading dimension `ld` (>= cols).
  void solve(double* b, int cols, int ld) const;
  /// Solves M^T X = B in place (the adjoint system), same layout as solve().
  void solve_adjoint(double* b, int cols, int ld) const;

 private:
  int n_ = 0;
  int lower_ = 0;
  int upper_ = 0;
  int width_ = 1;
  std::vector<double> data_;
};

}  // namespace porter::minco
