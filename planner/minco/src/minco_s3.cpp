#include "porter/minco/minco_s3.hpp"

#include <cmath>

namespace porter::minco {

template <int Dim>
bool MincoS3<Dim>::generate(const BoundaryState& head, const BoundaryState& tail,
                            const Waypoints& waypoints, const Eigen::VectorXd& durations_s) {
  const int n = static_cast<int>(durations_s.size());
  if (n < 1 || waypoints.cols() != n - 1) return false;
  for (int i = 0; i < n; ++i) {
    if (!(durations_s[i] > 0.0) || !std::isfinite(durations_s[i])) return false;
  }
  const int rows = kPieceCoeffs * n;
  if (n != num_pieces_) {
    num_pieces_ = n;
    system_.resize(rows, kPieceCoeffs, kPieceCoeffs);
    coeffs_.resize(rows, Dim);
    adjoint_.resize(rows, Dim);
  } else {
    system_.set_zero();
  }
  durations_ = durations_s;

  BandedSystem& m = system_;
  m(0, 0) = 1.0;
  m(1, 1) = 1.0;
  m(2, 2) = 2.0;
  coeffs_.setZero();
  coeffs_.row(0) = head.col(0).transpose();
  coeffs_.row(1) = head.col(1).transpose();
  coeffs_.row(2) = head.col(2).transpose();

  for (int i = 0; i < n - 1; ++i) {
    const double t1 = durations_s[i], t2 = t1 * t1, t3 = t2 * t1, t4 = t2 * t2, t5 = t4 * t1;
    const int r = kPieceCoeffs * i + 3;
    const int c = kPieceCoeffs * i;
    // jerk continuity
    m(r, c + 3) = 6.0;
    m(r, c + 4) = 24.0 * t1;
    m(r, c + 5) = 60.0 * t2;
    m(r, c + 9) = -6.0;
    // snap continuity
    m(r + 1, c + 4) = 24.0;
    m(r + 1, c + 5) = 120.0 * t1;
    m(r + 1, c + 10) = -24.0;
    // waypoint
    m(r + 2, c + 0) = 1.0;
    m(r + 2, c + 1) = t1;
    m(r + 2, c + 2) = t2;
    m(r + 2, c + 3) = t3;
    m(r + 2, c + 4) = t4;
    m(r + 2, c + 5) = t5;
    // position continuity
    m(r + 3, c + 0) = 1.0;
    m(r + 3, c + 1) = t1;
    m(r + 3, c + 2) = t2;
    m(r + 3, c + 3) = t3;
    m(r + 3, c + 4) = t4;
    m(r + 3, c + 5) = t5;
    m(r + 3, c + 6) = -1.0;
    // velocity continuity
    m(r + 4, c + 1) = 1.0;
    m(r + 4, c + 2) = 2.0 * t1;
    m(r + 4, c + 3) = 3.0 * t2;
    m(r + 4, c + 4) = 4.0 * t3;
    m(r + 4, c + 5) = 5.0 * t4;
    m(r + 4, c + 7) = -1.0;
    // acceleration continuity
    m(r + 5, c + 2) = 2.0;
    m(r + 5, c + 3) = 6.0 * t1;
    m(r + 5, c + 4) = 12.0 * t2;
    m(r + 5, c + 5) = 20.0 * t3;
    m(r + 5, c + 8) = -2.0;

    coeffs_.row(r + 2) = waypoints.col(i).transpose();
  }

  {
    const double t1 = durations_s[n - 1], t2 = t1 * t1, t3 = t2 * t1, t4 = t2 * t2, t5 = t4 * t1;
    const int r = rows - 3;
    const int c = rows - kPieceCoeffs;
    m(r, c + 0) = 1.0;
    m(r, c + 1) = t1;
    m(r, c + 2) = t2;
    m(r, c + 3) = t3;
    m(r, c + 4) = t4;
    m(r, c + 5) = t5;
    m(r + 1, c + 1) = 1.0;
    m(r + 1, c + 2) = 2.0 * t1;
    m(r + 1, c + 3) = 3.0 * t2;
    m(r + 1, c + 4) = 4.0 * t3;
    m(r + 1, c + 5) = 5.0 * t4;
    m(r + 2, c + 2) = 2.0;
    m(r + 2, c + 3) = 6.0 * t1;
    m(r + 2, c + 4) = 12.0 * t2;
    m(r + 2, c + 5) = 20.0 * t3;
    coeffs_.row(r) = tail.col(0).transpose();
    coeffs_.row(r + 1) = tail.col(1).transpose();
    coeffs_.row(r + 2) = tail.col(2).transpose();
  }

  if (!m.factorize_lu()) return false;
  m.solve(coeffs_.data(), Dim, Dim);
  return true;
}

template <int Dim>
double MincoS3<Dim>::energy(const Vector& w) const {
  double e = 0.0;
  for (int i = 0; i < num_pieces_; ++i) {
    const double t1 = durations_[i], t2 = t1 * t1, t3 = t2 * t1, t4 = t2 * t2, t5 = t4 * t1;
    const Vector c3 = coeffs_.row(6 * i + 3).transpose();
    const Vector c4 = coeffs_.row(6 * i + 4).transpose();
    const Vector c5 = coeffs_.row(6 * i + 5).transpose();
    const Vector wc3 = w.cwiseProduct(c3), wc4 = w.cwiseProduct(c4), wc5 = w.cwiseProduct(c5);
    e += 36.0 * c3.dot(wc3) * t1 + 144.0 * c4.dot(wc3) * t2 + 192.0 * c4.dot(wc4) * t3 +
         240.0 * c5.dot(wc3) * t3 + 720.0 * c5.dot(wc4) * t4 + 720.0 * c5.dot(wc5) * t5;
  }
  return e;
}

template <int Dim>
void MincoS3<Dim>::add_energy_gradient(const Vector& w, Coefficients& grad_c,
                                       Eigen::VectorXd& grad_t) const {
  for (int i = 0; i < num_pieces_; ++i) {
    const double t1 = durations_[i], t2 = t1 * t1, t3 = t2 * t1, t4 = t2 * t2, t5 = t4 * t1;
    const Vector wc3 = w.cwiseProduct(coeffs_.row(6 * i + 3).transpose());
    const Vector wc4 = w.cwiseProduct(coeffs_.row(6 * i + 4).transpose());
    const Vector wc5 = w.cwiseProduct(coeffs_.row(6 * i + 5).transpose());
    const Vector c3 = coeffs_.row(6 * i + 3).transpose();
    const Vector c4 = coeffs_.row(6 * i + 4).transpose();
    const Vector c5 = coeffs_.row(6 * i + 5).transpose();
    grad_c.row(6 * i + 3) += (72.0 * wc3 * t1 + 144.0 * wc4 * t2 + 240.0 * wc5 * t3).transpose();
    grad_c.row(6 * i + 4) += (144.0 * wc3 * t2 + 384.0 * wc4 * t3 + 720.0 * wc5 * t4).transpose();
    grad_c.row(6 * i + 5) += (240.0 * wc3 * t3 + 720.0 * wc4 * t4 + 1440.0 * wc5 * t5).transpose();
    grad_t[i] += 36.0 * c3.dot(wc3) + 288.0 * c4.dot(wc3) * t1 + 576.0 * c4.dot(wc4) * t2 +
                 720.0 * c5.dot(wc3) * t2 + 2880.0 * c5.dot(wc4) * t3 + 3600.0 * c5.dot(wc5) * t4;
  }
}

template <int Dim>
void MincoS3<Dim>::propagate_gradient(const Coefficients& partial_c,
                                      const Eigen::VectorXd& partial_t, Waypoints& grad_q,
                                      Eigen::VectorXd& grad_t, BoundaryState& grad_head,
                                      BoundaryState& grad_tail) {
  const int n = num_pieces_;
  const int rows = kPieceCoeffs * n;
  adjoint_ = partial_c;
  system_.solve_adjoint(adjoint_.data(), Dim, Dim);
  const Coefficients& g = adjoint_;

  grad_q.resize(Dim, n - 1);
  grad_t.resize(n);
  for (int k = 0; k < 3; ++k) {
    grad_head.col(k) = g.row(k).transpose();
    grad_tail.col(k) = g.row(rows - 3 + k).transpose();
  }
  for (int i = 0; i < n - 1; ++i) {
    const int r = kPieceCoeffs * i + 3;
    grad_q.col(i) = g.row(r + 2).transpose();
    const double t = durations_[i];
    const auto c = piece(i);
    const Vector vel = c.transpose() * basis(t, 1);
    const Vector acc = c.transpose() * basis(t, 2);
    const Vector jerk = c.transpose() * basis(t, 3);
    const Vector snap = c.transpose() * basis(t, 4);
    const Vector crackle = 120.0 * c.row(5).transpose();
    // dM/dT_i * C, row by row, is the next derivative of the junction's left-hand piece.
    grad_t[i] = partial_t[i] - (g.row(r).dot(snap.transpose()) +
                                g.row(r + 1).dot(crackle.transpose()) +
                                g.row(r + 2).dot(vel.transpose()) +
                                g.row(r + 3).dot(vel.transpose()) +
                                g.row(r + 4).dot(acc.transpose()) +
                                g.row(r + 5).dot(jerk.transpose()));
  }
  {
    const int r = rows - 3;
    const double t = durations_[n - 1];
    const auto c = piece(n - 1);
    const Vector vel = c.transpose() * basis(t, 1);
    const Vector acc = c.transpose() * basis(t, 2);
    const Vector jerk = c.transpose() * basis(t, 3);
    grad_t[n - 1] = partial_t[n - 1] - (g.row(r).dot(vel.transpose()) +
                                        g.row(r + 1).dot(acc.transpose()) +
                                        g.row(r + 2).dot(jerk.transpose()));
  }
}

template class MincoS3<1>;
template class MincoS3<2>;
template class MincoS3<8>;

}  // namespace porter::minco
