#include "porter/baselines/distance_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace porter::baselines {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// 1-D lower envelope of parabolas (Felzenszwalb & Huttenlocher 2012): d[q] = min_p (q-p)^2 + f[p].
void transform_1d(const double* f, int n, double* d, std::vector<int>& v, std::vector<double>& z) {
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  auto intersect = [f](int q, int p) {
    return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * (q - p));
  };
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] == kInf) continue;  // no site: contributes no parabola
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -kInf;
      z[1] = kInf;
      continue;
    }
    double s = intersect(q, v[static_cast<std::size_t>(k)]);
    while (s <= z[static_cast<std::size_t>(k)]) {  // z[0] = -inf ends the loop at k = 0
      --k;
      s = intersect(q, v[static_cast<std::size_t>(k)]);
    }
    ++k;
    v[static_cast<std::size_t>(k)] = q;
    z[static_cast<std::size_t>(k)] = s;
    z[static_cast<std::size_t>(k) + 1] = kInf;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) d[q] = kInf;
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[static_cast<std::size_t>(j) + 1] < q) ++j;
    const int p = v[static_cast<std::size_t>(j)];
    d[q] = double(q - p) * (q - p) + f[p];
  }
}

}  // namespace

void squared_distance_transform(std::vector<double>& f, const Eigen::Vector3i& dims) {
  const int nx = dims.x(), ny = dims.y(), nz = dims.z();
  const int longest = std::max({nx, ny, nz});
  std::vector<double> in(static_cast<std::size_t>(longest)), out(static_cast<std::size_t>(longest));
  std::vector<int> v;
  std::vector<double> z;
  auto at = [&](int i, int j, int k) -> double& {
    return f[static_cast<std::size_t>(i) + static_cast<std::size_t>(nx) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(ny) * k)];
  };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) in[static_cast<std::size_t>(i)] = at(i, j, k);
      transform_1d(in.data(), nx, out.data(), v, z);
      for (int i = 0; i < nx; ++i) at(i, j, k) = out[static_cast<std::size_t>(i)];
    }
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i) {
      for (int j = 0; j < ny; ++j) in[static_cast<std::size_t>(j)] = at(i, j, k);
      transform_1d(in.data(), ny, out.data(), v, z);
      for (int j = 0; j < ny; ++j) at(i, j, k) = out[static_cast<std::size_t>(j)];
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      for (int k = 0; k < nz; ++k) in[static_cast<std::size_t>(k)] = at(i, j, k);
      transform_1d(in.data(), nz, out.data(), v, z);
      for (int k = 0; k < nz; ++k) at(i, j, k) = out[static_cast<std::size_t>(k)];
    }
}

DistanceField DistanceField::build(const OccupancyGrid& occ, const Eigen::AlignedBox3d& region,
                                   double max_distance_m) {
  DistanceField field;
  field.max_distance_m_ = max_distance_m;
  if (occ.num_voxels() == 0) return field;
  const double res = occ.resolution_m();
  Eigen::Vector3i lo = Eigen::Vector3i::Zero(), hi = occ.dims() - Eigen::Vector3i::Ones();
  if (!region.isEmpty()) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::clamp(static_cast<int>(std::floor((region.min()[a] - occ.origin_W()[a]) / res)), 0, occ.dims()[a] - 1);
      hi[a] = std::clamp(static_cast<int>(std::floor((region.max()[a] - occ.origin_W()[a]) / res)), lo[a], occ.dims()[a] - 1);
    }
  }
  const Eigen::Vector3i dims = (hi - lo + Eigen::Vector3i::Ones()).cwiseMax(3);
  const std::size_t n = static_cast<std::size_t>(dims.x()) * dims.y() * dims.z();
  std::vector<double> outside(n), inside(n);
  for (int k = 0; k < dims.z(); ++k)
    for (int j = 0; j < dims.y(); ++j)
      for (int i = 0; i < dims.x(); ++i) {
        const bool occupied = occ.occupied(lo.x() + i, lo.y() + j, lo.z() + k);
        const std::size_t u = static_cast<std::size_t>(i) + static_cast<std::size_t>(dims.x()) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims.y()) * k);
        outside[u] = occupied ? 0.0 : kInf;  // distance to occupied centres
        inside[u] = occupied ? kInf : 0.0;   // distance to free centres
      }
  squared_distance_transform(outside, dims);
  squared_distance_transform(inside, dims);
  const Eigen::Vector3d origin = occ.voxel_center_W(lo.x(), lo.y(), lo.z());
  field.grid_ = backend::SdfGrid(origin, res, dims);
  auto& values = field.grid_.values();
  for (std::size_t u = 0; u < n; ++u) {
    double d;
    if (outside[u] > 0.0) {
      d = std::sqrt(outside[u]) * res - 0.5 * res;
    } else {
      d = inside[u] == kInf ? -max_distance_m : -(std::sqrt(inside[u]) * res - 0.5 * res);
    }
    values[u] = static_cast<float>(std::clamp(std::isfinite(d) ? d : max_distance_m, -max_distance_m, max_distance_m));
  }
  return field;
}

}  // namespace porter::baselines
