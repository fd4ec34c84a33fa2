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

/// As squared_distance_3d, exact only where the caller reads: at (x, y, z) with x = x0 + i step
/// and y = y0 + j step (every z). The x pass runs over every row that holds a site (a row without
/// one stays kFar), the y pass only over the columns x = x0 + i step, the z pass only over the
/// lines (x0 + i step, y0 + j step); other entries hold partial transforms. Reading a cell
/// centre of every 2 x 2 x 2 voxels this does 1 + 1/2 + 1/4 of the full transform's passes.
/// `far2`: a caller that caps distances may say from which squared distance on a value no longer
/// matters; every result >= far2 may then come out as any value >= far2 (lines that hold only
/// such values are skipped).
inline void squared_distance_3d_sampled(const std::vector<std::uint8_t>& site, int nx, int ny, int nz, int x0, int y0,
                                        int step, std::vector<std::int32_t>& d2, std::int32_t far2 = kFar) {
  d2.resize(site.size());
  for (std::size_t i = 0; i < site.size(); ++i) d2[i] = site[i] ? 0 : kFar;
  std::vector<std::int32_t> in;
  std::vector<int> v;
  std::vector<double> zb;
  const std::int64_t sy = nx, sz = static_cast<std::int64_t>(nx) * ny;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y) {
      const std::size_t first = static_cast<std::size_t>(y * sy + z * sz);
      const auto row = site.begin() + static_cast<std::ptrdiff_t>(first);
      if (std::find(row, row + nx, std::uint8_t{1}) == row + nx) continue;
      // Along a row of binary sites the transform is the squared gap to the nearest site: two
      // sweeps (the same values edt_1d gives on 0 / kFar input).
      std::int32_t* f = &d2[first];
      int last = -1;
      for (int q = 0; q < nx; ++q) {
        if (row[q]) last = q;
        f[q] = last < 0 ? kFar : (q - last) * (q - last);
      }
      last = -1;
      for (int q = nx - 1; q >= 0; --q) {
        if (row[q]) last = q;
        if (last >= 0) f[q] = std::min(f[q], (last - q) * (last - q));
        if (f[q] >= far2) f[q] = kFar;
      }
    }
  // A line of kFar stays kFar; values >= far2 only make results >= far2.
  auto line = [&](std::int32_t* f, int n, std::int64_t stride) {
    bool any = false;
    for (int q = 0; q < n && !any; ++q) any = f[q * stride] < kFar;
    if (!any) return;
    edt_1d(f, n, stride, in, v, zb);
    for (int q = 0; q < n; ++q)
      if (f[q * stride] >= far2) f[q * stride] = kFar;
  };
  for (int z = 0; z < nz; ++z)
    for (int x = x0; x < nx; x += step) line(&d2[static_cast<std::size_t>(x + z * sz)], ny, sy);
  for (int y = y0; y < ny; y += step)
    for (int x = x0; x < nx; x += step) line(&d2[static_cast<std::size_t>(x + y * sy)], nz, sz);
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
  // dilate_box(set, nx, ny, nz, 0, 1) in place: along each axis, from the last cell down, a cell
  // takes its predecessor's (not yet updated) value.
  const std::int64_t sy = nx, sz = static_cast<std::int64_t>(nx) * ny;
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y) {
      std::uint8_t* r = &set[static_cast<std::size_t>(y * sy + z * sz)];
      for (int x = nx - 1; x >= 1; --x) r[x] |= r[x - 1];
    }
  for (int z = 0; z < nz; ++z)
    for (int y = ny - 1; y >= 1; --y) {
      std::uint8_t* r = &set[static_cast<std::size_t>(y * sy + z * sz)];
      const std::uint8_t* p = r - sy;
      for (int x = 0; x < nx; ++x) r[x] |= p[x];
    }
  for (int z = nz - 1; z >= 1; --z) {
    std::uint8_t* r = &set[static_cast<std::size_t>(z * sz)];
    const std::uint8_t* p = r - sz;
    for (std::int64_t i = 0; i < sz; ++i) r[i] |= p[i];
  }
}

}  // namespace porter::planner::edt
