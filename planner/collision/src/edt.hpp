#pragma once
// Exact squared Euclidean distance transform in 1D (Felzenszwalb & Huttenlocher), applied along
// each axis of a grid by the callers. Private to porter_collision.

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace porter::planner::edt {

/// "No site" (a large finite value, so the lower envelope stays exact).
constexpr std::int32_t kFar = 1 << 28;

/// In-place 1D squared distance transform of f[0], f[stride], ..., f[(n-1) stride]; scratch
/// vectors are reused between calls.
inline void edt_1d(std::int32_t* f, int n, std::int64_t stride, std::vector<std::int32_t>& in, std::vector<int>& v,
                   std::vector<double>& z) {
  in.resize(static_cast<std::size_t>(n));
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  for (int q = 0; q < n; ++q) in[static_cast<std::size_t>(q)] = f[q * stride];
  auto g = [&](int q) { return static_cast<double>(in[static_cast<std::size_t>(q)]) + static_cast<double>(q) * q; };
  std::size_t k = 0;
  v[0] = 0;
  z[0] = -std::numeric_limits<double>::infinity();
  z[1] = std::numeric_limits<double>::infinity();
  for (int q = 1; q < n; ++q) {
    double s = (g(q) - g(v[k])) / (2.0 * (q - v[k]));
    while (s <= z[k]) {
      --k;
      s = (g(q) - g(v[k])) / (2.0 * (q - v[k]));
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const int p = v[k];
    const std::int64_t d = static_cast<std::int64_t>(q - p) * (q - p) + in[static_cast<std::size_t>(p)];
    f[q * stride] = static_cast<std::int32_t>(std::min<std::int64_t>(d, kFar));
  }
}

/// Squared distances (in cells) from every cell of an nx x ny x nz grid (x fastest) to the nearest
/// cell whose `site` is true, computed in place over `d2` (resized).
inline void squared_distance_3d(const std::vector<std::uint8_t>& site, int nx, int ny, int nz,
                                std::vector<std::int32_t>& d2) {
  d2.resize(site.size());
  for (std::size_t i = 0; i < site.size(); ++i) d2[i] = site[i] ? 0 : kFar;
  std::vector<std::int32_t> in;
  std::vector<int> v;
  std::vector<double> zb;
  const std::int64_t sx = 1, sy = nx, sz = static_cast<std::int64_t>(nx) * ny;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y) edt_1d(&d2[static_cast<std::size_t>(y * sy + z * sz)], nx, sx, in, v, zb);
  for (int z = 0; z < nz; ++z)
    for (int x = 0; x < nx; ++x) edt_1d(&d2[static_cast<std::size_t>(x + z * sz)], ny, sy, in, v, zb);
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x) edt_1d(&d2[static_cast<std::size_t>(x + y * sy)], nz, sz, in, v, zb);
}

/// Separable box dilation of `set` (x fastest): every set cell also sets the cells up to `back`
/// before and `forward` after it along each axis, a box of (back + 1 + forward)^3 cells.
inline void dilate_box(std::vector<std::uint8_t>& set, int nx, int ny, int nz, int back, int forward) {
  const int n[3] = {nx, ny, nz};
  const std::int64_t stride[3] = {1, nx, static_cast<std::int64_t>(nx) * ny};
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<std::uint8_t> out = set;
    for (std::size_t i = 0; i < set.size(); ++i) {
      if (!set[i]) continue;
      const auto coord = static_cast<int>((static_cast<std::int64_t>(i) / stride[axis]) % n[axis]);
      for (int k = 1; k <= back && coord - k >= 0; ++k) out[i - static_cast<std::size_t>(k * stride[axis])] = 1;
      for (int k = 1; k <= forward && coord + k < n[axis]; ++k) out[i + static_cast<std::size_t>(k * stride[axis])] = 1;
    }
    set.swap(out);
  }
}

/// The 26-neighbourhood dilation of `set` (x fastest). After it, the squared distance
/// transform's value at a cell is the squared smallest gap between that cell's box and a box of
/// the original set.
inline void dilate26(std::vector<std::uint8_t>& set, int nx, int ny, int nz) { dilate_box(set, nx, ny, nz, 1, 1); }

/// Every set cell also sets its successor along each axis (2 x 2 x 2 boxes). After it, the
/// squared distance transform's value at cell i is the squared distance from the lattice vertex
/// at i (the minimum corner of cell i) to the nearest box of the original set: along one axis,
/// vertex v is max(w - v, v - (w + 1), 0) from cell w, its distance to the pair {w, w + 1}.
inline void dilate_to_vertices(std::vector<std::uint8_t>& set, int nx, int ny, int nz) {
  dilate_box(set, nx, ny, nz, 0, 1);
}

}  // namespace porter::planner::edt
