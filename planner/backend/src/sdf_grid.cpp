#include "porter/backend/sdf_grid.hpp"

#include <algorithm>
#include <cmath>

namespace porter::backend {

SdfGrid::SdfGrid(const Eigen::Vector3d& origin, double resolution_m, const Eigen::Vector3i& dims)
    : origin_(origin),
      h_(resolution_m),
      inv_h_(1.0 / resolution_m),
      dims_(dims.cwiseMax(3)),
      bounds_(origin, origin + resolution_m * (dims.cwiseMax(3) - Eigen::Vector3i::Ones()).cast<double>()),
      smooth_bounds_(bounds_.min() + Eigen::Vector3d::Constant(0.5 * resolution_m),
                     bounds_.max() - Eigen::Vector3d::Constant(0.5 * resolution_m)),
      values_(static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z(), 0.0f) {}

SdfGrid SdfGrid::covering(const Eigen::AlignedBox3d& box, double resolution_m) {
  // Half a cell of margin on each side: the B-spline is defined from the first node + h/2.
  const Eigen::Vector3d extent = box.sizes() + Eigen::Vector3d::Constant(resolution_m);
  Eigen::Vector3i dims;
  for (int a = 0; a < 3; ++a) {
    dims[a] = std::max(3, static_cast<int>(std::ceil(extent[a] / resolution_m - 1e-9)) + 1);
  }
  return SdfGrid(box.min() - Eigen::Vector3d::Constant(0.5 * resolution_m), resolution_m, dims);
}

double SdfGrid::smooth(const Eigen::Vector3d& p, Eigen::Vector3d* grad) const {
  // Per axis: nearest node c, offset t in [-1/2, 1/2]; weights of nodes c-1, c, c+1 are
  // (1/2 - t)^2 / 2, 3/4 - t^2, (1/2 + t)^2 / 2 and their derivatives -(1/2 - t), -2t, 1/2 + t.
  double w[3][3], dw[3][3];
  int c[3];
  for (int a = 0; a < 3; ++a) {
    double u = (p[a] - origin_[a]) * inv_h_;
    const double umax = static_cast<double>(dims_[a]) - 1.5;
    u = u < 0.5 ? 0.5 : (u > umax ? umax : u);
    int i = static_cast<int>(u + 0.5);
    if (i > dims_[a] - 2) i = dims_[a] - 2;
    if (i < 1) i = 1;
    const double t = u - i;
    const double l = 0.5 - t, r = 0.5 + t;
    c[a] = i - 1;
    w[a][0] = 0.5 * l * l;
    w[a][1] = 0.75 - t * t;
    w[a][2] = 0.5 * r * r;
    dw[a][0] = -l;
    dw[a][1] = -2.0 * t;
    dw[a][2] = r;
  }
  const std::size_t sy = static_cast<std::size_t>(dims_.x());
  const std::size_t sz = sy * static_cast<std::size_t>(dims_.y());
  const float* base = values_.data() + index(c[0], c[1], c[2]);
  double value = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
  for (int k = 0; k < 3; ++k) {
    double vk = 0.0, gxk = 0.0, gyk = 0.0;
    for (int j = 0; j < 3; ++j) {
      const float* row = base + k * sz + j * sy;
      const double r0 = row[0], r1 = row[1], r2 = row[2];
      const double vx = w[0][0] * r0 + w[0][1] * r1 + w[0][2] * r2;
      const double dx = dw[0][0] * r0 + dw[0][1] * r1 + dw[0][2] * r2;
      vk += w[1][j] * vx;
      gxk += w[1][j] * dx;
      gyk += dw[1][j] * vx;
    }
    value += w[2][k] * vk;
    gx += w[2][k] * gxk;
    gy += w[2][k] * gyk;
    gz += dw[2][k] * vk;
  }
  if (grad) *grad = Eigen::Vector3d(gx, gy, gz) * inv_h_;
  return value;
}

double SdfGrid::trilinear(const Eigen::Vector3d& p, Eigen::Vector3d* grad) const {
  double f[3];
  int i[3];
  for (int a = 0; a < 3; ++a) {
    double u = (p[a] - origin_[a]) * inv_h_;
    const double umax = static_cast<double>(dims_[a] - 1);
    u = u < 0.0 ? 0.0 : (u > umax ? umax : u);
    int c = static_cast<int>(u);
    if (c > dims_[a] - 2) c = dims_[a] - 2;
    i[a] = c;
    f[a] = u - c;
  }
  const std::size_t sx = 1;
  const std::size_t sy = static_cast<std::size_t>(dims_.x());
  const std::size_t sz = sy * static_cast<std::size_t>(dims_.y());
  const float* v = values_.data() + index(i[0], i[1], i[2]);
  const double c000 = v[0], c100 = v[sx], c010 = v[sy], c110 = v[sx + sy];
  const double c001 = v[sz], c101 = v[sx + sz], c011 = v[sy + sz], c111 = v[sx + sy + sz];
  const double fx = f[0], fy = f[1], fz = f[2];
  // Interpolate along x, then y, then z.
  const double c00 = c000 + fx * (c100 - c000);
  const double c10 = c010 + fx * (c110 - c010);
  const double c01 = c001 + fx * (c101 - c001);
  const double c11 = c011 + fx * (c111 - c011);
  const double c0 = c00 + fy * (c10 - c00);
  const double c1 = c01 + fy * (c11 - c01);
  const double value = c0 + fz * (c1 - c0);
  if (grad) {
    const double dx00 = c100 - c000, dx10 = c110 - c010, dx01 = c101 - c001, dx11 = c111 - c011;
    const double dx0 = dx00 + fy * (dx10 - dx00);
    const double dx1 = dx01 + fy * (dx11 - dx01);
    const double gx = dx0 + fz * (dx1 - dx0);
    const double gy = (c10 - c00) + fz * ((c11 - c01) - (c10 - c00));
    const double gz = c1 - c0;
    *grad = Eigen::Vector3d(gx, gy, gz) * inv_h_;
  }
  return value;
}

}  // namespace porter::backend
