#include "porter/mapping/rolling_map.hpp"

#include <algorithm>
#include <cmath>

namespace porter::mapping {

namespace {
// Per-cloud marks, one bit per voxel (a bitset keeps the marks of a 10 M-voxel window in
// 1.25 MB, close to the cache, where the rays' scattered accesses land).
inline bool test_bit(const std::vector<std::uint64_t>& b, std::int64_t k) {
  return (b[static_cast<std::size_t>(k >> 6)] >> (k & 63)) & 1u;
}
inline void set_bit(std::vector<std::uint64_t>& b, std::int64_t k) {
  b[static_cast<std::size_t>(k >> 6)] |= std::uint64_t{1} << (k & 63);
}
inline void clear_bit(std::vector<std::uint64_t>& b, std::int64_t k) {
  b[static_cast<std::size_t>(k >> 6)] &= ~(std::uint64_t{1} << (k & 63));
}
const float kUnknown = std::numeric_limits<float>::quiet_NaN();

// OctoMap's logodds(): computed in double, stored as float.
float logodds(double p) { return static_cast<float>(std::log(p / (1.0 - p))); }
}  // namespace

RollingMap::RollingMap(const RollingMapParams& params)
    : params_(params), inv_res_(1.0 / params.resolution_m) {
  params_.dims = params_.dims.cwiseMax(2);
  stride_y_ = params_.dims.x();
  stride_z_ = static_cast<std::int64_t>(params_.dims.x()) * params_.dims.y();
  const std::size_t n = static_cast<std::size_t>(stride_z_ * params_.dims.z());
  log_odds_.assign(n, kUnknown);
  touched_.assign((n + 63) / 64, 0);
  settled_free_.assign((n + 63) / 64, 0);
  ray_end_.assign((n + 63) / 64, 0);
  block_dims_ = (params_.dims.array() + ((1 << kBlockShift) - 1)).matrix() / (1 << kBlockShift);
  block_rev_.assign(static_cast<std::size_t>(block_dims_.prod()), 0);
  states_.assign(static_cast<std::size_t>(block_dims_.prod()) * kBlockWords, 0);
  window_min_ = Eigen::Vector3i(kKeyOffset - params_.dims.x() / 2, kKeyOffset - params_.dims.y() / 2,
                                key_of(params_.z_min_m));
  hit_log_ = logodds(params_.prob_hit);
  miss_log_ = logodds(params_.prob_miss);
  clamp_min_log_ = logodds(params_.clamp_min);
  clamp_max_log_ = logodds(params_.clamp_max);
  occupancy_log_ = logodds(params_.occupancy_threshold);
}

bool RollingMap::needs_recenter(double x_m, double y_m, double distance_m) const {
  if (!std::isfinite(x_m) || !std::isfinite(y_m)) return false;
  const double cx = (window_min_.x() - kKeyOffset + 0.5 * params_.dims.x()) * params_.resolution_m;
  const double cy = (window_min_.y() - kKeyOffset + 0.5 * params_.dims.y()) * params_.resolution_m;
  return std::abs(x_m - cx) > distance_m || std::abs(y_m - cy) > distance_m;
}

void RollingMap::set_state(std::int64_t k, int state) {
  const std::int64_t nx = params_.dims.x(), ny = params_.dims.y();
  const int sx = static_cast<int>(k % nx), r = static_cast<int>(k / nx), sy = r % static_cast<int>(ny),
            sz = r / static_cast<int>(ny);
  const std::size_t b = block_index(sx >> kBlockShift, sy >> kBlockShift, sz >> kBlockShift);
  const int i = (sx & 7) + 8 * (sy & 7) + 64 * (sz & 7);
  std::uint64_t& w = states_[b * kBlockWords + static_cast<std::size_t>(i >> 5)];
  const int shift = 2 * (i & 31);
  w = (w & ~(std::uint64_t{3} << shift)) | (static_cast<std::uint64_t>(state) << shift);
  block_rev_[b] = revision_;
}

void RollingMap::clear_slots(int axis, int first, int count) {
  if (count <= 0) return;
  for (int s = first; s < first + count; ++s) clear_plane_states(axis, s);
  // The log-odds: per row a run of `count` floats (x), or `count` whole rows per layer (y).
  const Eigen::Vector3i& n = params_.dims;
  for (int z = 0; z < n.z(); ++z) {
    if (axis == 0) {
      for (int y = 0; y < n.y(); ++y) {
        float* row = &log_odds_[static_cast<std::size_t>(stride_y_ * y + stride_z_ * z + first)];
        std::fill(row, row + count, kUnknown);
      }
    } else {
      float* rows = &log_odds_[static_cast<std::size_t>(stride_y_ * first + stride_z_ * z)];
      std::fill(rows, rows + static_cast<std::ptrdiff_t>(count) * n.x(), kUnknown);
    }
  }
}

void RollingMap::clear_plane_states(int axis, int s) {
  const Eigen::Vector3i& nb = block_dims_;
  const int b = s >> kBlockShift, o = s & 7;
  // The plane's voxels in each block it crosses: x = o (2 bits every 16, in every word) or
  // y = o (one 16-bit row in every other word).
  const std::uint64_t x_mask = std::uint64_t{0x0003000300030003} << (2 * o);
  const std::uint64_t y_mask = std::uint64_t{0xFFFF} << (16 * (o & 3));
  for (int bz = 0; bz < nb.z(); ++bz)
    for (int bo = 0; bo < (axis == 0 ? nb.y() : nb.x()); ++bo) {
      const std::size_t bi = axis == 0 ? block_index(b, bo, bz) : block_index(bo, b, bz);
      block_rev_[bi] = revision_;
      std::uint64_t* w = &states_[bi * kBlockWords];
      if (axis == 0) {
        for (int j = 0; j < kBlockWords; ++j) w[j] &= ~x_mask;
      } else {
        for (int z = 0; z < 8; ++z) w[(o >> 2) + 2 * z] &= ~y_mask;
      }
    }
}

bool RollingMap::center_on(double x_m, double y_m) {
  const double limit = (kKeyOffset / 2) * params_.resolution_m;  // keeps every window key valid
  if (!(std::abs(x_m) < limit && std::abs(y_m) < limit)) return false;
  const Eigen::Vector3i& n = params_.dims;
  const int new_min[2] = {key_of(x_m) - n.x() / 2, key_of(y_m) - n.y() / 2};
  bool moved = false;
  for (int axis = 0; axis < 2; ++axis) {
    const int old_min = window_min_[axis];
    const int shift = new_min[axis] - old_min;
    if (shift == 0) continue;
    if (!moved) ++revision_;
    moved = true;
    // The keys that leave, [k0, k0 + count), as slots: at most two runs (wrapping at n).
    const int count = std::min(std::abs(shift), n[axis]);
    const int k0 = std::abs(shift) >= n[axis] ? 0 : (shift > 0 ? old_min : new_min[axis] + n[axis]);
    const int s0 = k0 % n[axis];
    const int first_run = std::min(count, n[axis] - s0);
    clear_slots(axis, s0, first_run);
    clear_slots(axis, 0, count - first_run);
    window_min_[axis] = new_min[axis];
  }
  return moved;
}

void RollingMap::clear() {
  ++revision_;
  std::fill(log_odds_.begin(), log_odds_.end(), kUnknown);
  std::fill(block_rev_.begin(), block_rev_.end(), revision_);
  std::fill(states_.begin(), states_.end(), 0);
}

VoxelState RollingMap::state(const Eigen::Vector3i& key) const {
  const float v = log_odds(key);
  if (v != v) return VoxelState::unknown;
  return occupied(v) ? VoxelState::occupied : VoxelState::free;
}

float RollingMap::log_odds(const Eigen::Vector3i& key) const {
  if (!in_window(key)) return kUnknown;
  return log_odds_[static_cast<std::size_t>(slot(key))];
}

std::int64_t RollingMap::count(VoxelState s) const {
  std::int64_t c = 0;
  for (float v : log_odds_) {
    const VoxelState vs = v != v ? VoxelState::unknown : (occupied(v) ? VoxelState::occupied : VoxelState::free);
    c += vs == s;
  }
  return c;
}

// 3D-DDA (Amanatides & Woo) with OctoMap's computeRayKeys conventions: float origin and
// direction, double tMax/tDelta, stop at the end key or once the travelled distance exceeds the
// ray length; here also once the ray leaves the window (it never comes back: every axis moves
// monotonically).
void RollingMap::cast(const Eigen::Vector3f& origin, const Eigen::Vector3i& key_origin,
                      const Eigen::Vector3f& end, IntegrateStats& stats) {
  const Eigen::Vector3i key_end = key_of(end.cast<double>());
  if (key_end == key_origin) return;
  ++stats.rays;
  const Eigen::Vector3i& n = params_.dims;
  // Locals, so the marks' stores (uint64) cannot alias them.
  std::uint64_t* const touched = touched_.data();
  std::uint64_t traversed = 1;
  int s[3];
  for (int i = 0; i < 3; ++i) s[i] = key_origin[i] % n[i];
  std::int64_t idx = s[0] + stride_y_ * s[1] + stride_z_ * s[2];
  // A hit stays a hit: hits are listed and updated first.
  const auto mark_free = [touched](std::int64_t k) { touched[k >> 6] |= std::uint64_t{1} << (k & 63); };
  mark_free(idx);

  Eigen::Vector3f direction = end - origin;
  const float length = direction.norm();
  direction /= length;
  int step[3], left[3];  // left: steps along the axis before the ray leaves the window
  double t_max[3], t_delta[3];
  int key[3] = {key_origin.x(), key_origin.y(), key_origin.z()};
  for (int i = 0; i < 3; ++i) {
    step[i] = direction[i] > 0.0f ? 1 : (direction[i] < 0.0f ? -1 : 0);
    left[i] = step[i] > 0 ? window_min_[i] + n[i] - 1 - key[i] : (step[i] < 0 ? key[i] - window_min_[i] : 0);
    if (step[i] != 0) {
      double border = key_to_coord(key[i]);
      border += static_cast<float>(step[i] * params_.resolution_m * 0.5);
      t_max[i] = (border - origin[i]) / direction[i];
      t_delta[i] = params_.resolution_m / std::fabs(direction[i]);
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  // OctoMap's loop: step along the axis of the smallest tMax (ties: x < y ? (x < z ? x : z) :
  // (y < z ? y : z)); stop at the end key, or once the smallest tMax passes the length; here
  // also once the ray leaves the window. Written out per axis so that the ray's state stays in
  // registers (indexing arrays by the axis sends every step through memory).
  double tx = t_max[0], ty = t_max[1], tz = t_max[2];
  const double dx = t_delta[0], dy = t_delta[1], dz = t_delta[2];
  const double len = length;
  int kx = key[0], ky = key[1], kz = key[2];
  const int ex = key_end.x(), ey = key_end.y(), ez = key_end.z();
  int lx = left[0], ly = left[1], lz = left[2];
  int sx = s[0], sy = s[1], sz = s[2];
  const int nx = n[0], ny = n[1], nz = n[2];
  const int gx = step[0], gy = step[1], gz = step[2];
  const std::int64_t ix = gx, iy = gy * stride_y_, iz = gz * stride_z_;
  const std::int64_t wx = nx, wy = static_cast<std::int64_t>(ny) * stride_y_, wz = static_cast<std::int64_t>(nz) * stride_z_;
  for (;;) {
    const int dim = tx < ty ? (tx < tz ? 0 : 2) : (ty < tz ? 1 : 2);
    if (dim != 1) {
      if (dim == 0) {
        kx += gx;
        tx += dx;
        if (kx == ex && ky == ey && kz == ez) break;
        if (tx > len && ty > len && tz > len) break;
        if (--lx < 0) break;
        sx += gx;
        idx += ix;
        if (sx == nx) {
          sx = 0;
          idx -= wx;
        } else if (sx < 0) {
          sx = nx - 1;
          idx += wx;
        }
      } else {
        kz += gz;
        tz += dz;
        if (kx == ex && ky == ey && kz == ez) break;
        if (tx > len && ty > len && tz > len) break;
        if (--lz < 0) break;
        sz += gz;
        idx += iz;
        if (sz == nz) {
          sz = 0;
          idx -= wz;
        } else if (sz < 0) {
          sz = nz - 1;
          idx += wz;
        }
      }
    } else {
      ky += gy;
      ty += dy;
      if (kx == ex && ky == ey && kz == ez) break;
      if (tx > len && ty > len && tz > len) break;
      if (--ly < 0) break;
      sy += gy;
      idx += iy;
      if (sy == ny) {
        sy = 0;
        idx -= wy;
      } else if (sy < 0) {
        sy = ny - 1;
        idx += wy;
      }
    }
    mark_free(idx);
    ++traversed;
  }
  stats.voxels_traversed += traversed;
}

void RollingMap::shadow_behind(const Eigen::Vector3f& origin, const Eigen::Vector3f& end, IntegrateStats& stats) {
  const Eigen::Vector3f ray = end - origin;
  const float length = ray.norm();
  if (!(length > 0.0f)) return;
  const Eigen::Vector3d u = (ray / length).cast<double>();
  const Eigen::Vector3d e = end.cast<double>();
  const Eigen::Vector3i key_end = key_of(e);
  // Sampled every quarter voxel from the hit point on: each voxel the ray enters behind it is
  // visited (a voxel it only clips at a corner, shorter than a quarter voxel, may be skipped).
  const double step = 0.25 * params_.resolution_m;
  const int samples = static_cast<int>(std::ceil(params_.new_surface_shadow_m / step));
  shadow_below(key_end, stats);
  Eigen::Vector3i last = key_end;
  for (int j = 1; j <= samples; ++j) {
    const Eigen::Vector3i key = key_of(Eigen::Vector3d(e + u * (step * j)));
    if (key == last) continue;
    last = key;
    if (!in_window(key)) return;  // every axis moves monotonically: it does not come back
    const Shade s = shade(slot(key), stats);
    if (s == Shade::end) return;
    if (s == Shade::set) shadow_below(key, stats);
  }
}

void RollingMap::shadow_below(const Eigen::Vector3i& key, IntegrateStats& stats) {
  for (Eigen::Vector3i below(key.x(), key.y(), key.z() - 1); below.z() >= window_min_.z(); --below.z())
    if (shade(slot(below), stats) == Shade::end) return;
}

RollingMap::Shade RollingMap::shade(std::int64_t k, IntegrateStats& stats) {
  if (test_bit(touched_, k)) return Shade::seen;  // crossed by a ray of this cloud: seen free now
  float& v = log_odds_[static_cast<std::size_t>(k)];
  // A run of shadow goes through free voxels and ends at the first one that is not free: behind
  // a static object's surface lies its unseen (unknown) or occupied inside, and the free space
  // past that is not what the new surface hides.
  if (v != v || v >= occupancy_log_) return Shade::end;
  v = shadow_log_odds();
  set_state(k, 2);
  ++stats.shadowed;
  return Shade::set;
}

IntegrateStats RollingMap::integrate(const Eigen::Vector3f& origin_W, const std::vector<Eigen::Vector3f>& points_W,
                                     const IntegrateOptions& options) {
  IntegrateStats stats;
  stats.points = points_W.size();
  ++revision_;
  // Keys exist for |coord| < 32767 voxels; the window lies well inside that.
  const float key_limit = static_cast<float>((kKeyOffset - 2) * params_.resolution_m);
  const auto representable = [&](const Eigen::Vector3f& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() < key_limit; };
  if (!representable(origin_W) || !in_window(key_of(origin_W.cast<double>()))) {
    stats.origin_outside = true;
    return stats;
  }
  const Eigen::Vector3i key_origin = key_of(origin_W.cast<double>());
  occupied_list_.clear();
  occupied_ends_.clear();
  new_surfaces_.clear();
  end_list_.clear();
  ray_ends_.clear();
  const float max_range = static_cast<float>(options.max_range_m);
  const float ground = static_cast<float>(std::max(options.ground_height_m, -1e30));

  // Pass 1: classify, mark hit voxels (hits win over misses), one ray per endpoint voxel.
  for (const Eigen::Vector3f& p : points_W) {
    if (!p.allFinite()) {
      ++stats.invalid;
      continue;
    }
    Eigen::Vector3f end = p;
    bool hit = true;
    if (max_range >= 0.0f && (p - origin_W).norm() > max_range) {
      end = origin_W + (p - origin_W).normalized() * max_range;
      hit = false;
      ++stats.beyond_range;
    } else if (p.z() < ground) {
      hit = false;
      ++stats.ground;
    }
    if (!representable(end)) {
      ++stats.invalid;
      continue;
    }
    const Eigen::Vector3i key = key_of(end.cast<double>());
    if (!in_window(key)) {
      if (hit) ++stats.outside_window;
      ray_ends_.push_back(end);  // free part inside the window; not deduplicated
      continue;
    }
    const std::int64_t k = slot(key);
    if (hit) {
      ++stats.hits;
      if (test_bit(touched_, k)) continue;  // pass 1 touches hits only
      occupied_list_.push_back(k);
      occupied_ends_.push_back(end);
      set_bit(touched_, k);
      ray_ends_.push_back(end);
    } else {
      if (test_bit(touched_, k) || test_bit(ray_end_, k)) continue;
      end_list_.push_back(k);
      set_bit(ray_end_, k);
      ray_ends_.push_back(end);
    }
  }
  // A ray end marked before the voxel turned out to be a hit keeps its ray: harmless (the ray
  // excludes its end voxel, and that voxel is a hit).

  // Pass 2: cast the rays.
  for (const Eigen::Vector3f& end : ray_ends_) cast(origin_W, key_origin, end, stats);

  // Pass 3: one update per voxel, then clear the marks. Hits first (they are listed); every
  // other touched voxel is free, and is found by scanning the bitset, which visits the log-odds
  // in memory order instead of the rays' scattered order.
  // A voxel's state: 0 unknown, 1 free, 2 occupied; a change stamps its block.
  const float occ = occupancy_log_;
  const auto state_of = [occ](float v) { return v != v ? 0 : (v >= occ ? 2 : 1); };
  const bool shadows = params_.new_surface_shadow_m > 0.0;
  for (std::size_t i = 0; i < occupied_list_.size(); ++i) {
    const std::int64_t k = occupied_list_[i];
    float& v = log_odds_[static_cast<std::size_t>(k)];
    const int before = state_of(v);
    if (v != v) v = 0.0f;
    v += hit_log_;
    if (v > clamp_max_log_) v = clamp_max_log_;
    const int after = state_of(v);
    if (after != before) {
      set_state(k, after);
      if (after == 2) {
        if (test_bit(settled_free_, k)) new_surfaces_.push_back(i);
        clear_bit(settled_free_, k);
      }
    }
    clear_bit(touched_, k);
  }
  stats.new_surfaces = new_surfaces_.size();
  // Before the free updates clear them, the touched marks say which voxels a ray of this cloud
  // crossed: those are seen free now and keep no shadow.
  if (shadows)
    for (std::size_t i : new_surfaces_) shadow_behind(origin_W, occupied_ends_[i], stats);
  std::uint64_t free_updates = 0;
  // The touched voxels are sparse in the 41 MB array: ask for the cache lines (16 floats, 16
  // bits of a word) a few words ahead of the ones being updated.
  constexpr std::size_t kAhead = 8;
  const std::size_t words = touched_.size();
  for (std::size_t w = 0; w < words; ++w) {
    if (w + kAhead < words) {
      const std::uint64_t ahead = touched_[w + kAhead];
      if (ahead != 0) {
        const float* line = log_odds_.data() + ((w + kAhead) << 6);
        for (int q = 0; q < 4; ++q) {
          if ((ahead >> (16 * q)) & 0xFFFFu) __builtin_prefetch(line + 16 * q, 1);
        }
      }
    }
    std::uint64_t bits = touched_[w];
    if (bits == 0) continue;
    touched_[w] = 0;
    std::uint64_t settled = settled_free_[w];
    while (bits) {
      const int b = __builtin_ctzll(bits);
      const std::uint64_t bit = bits & (~bits + 1);
      bits &= bits - 1;
      const std::size_t k = (w << 6) + static_cast<std::size_t>(b);
      float& v = log_odds_[k];
      const int before = state_of(v);
      if (v != v) v = 0.0f;
      v += miss_log_;
      if (v < clamp_min_log_) v = clamp_min_log_;
      const int after = state_of(v);
      if (after != before) set_state(static_cast<std::int64_t>(k), after);
      settled = v == clamp_min_log_ ? (settled | bit) : (settled & ~bit);
      ++free_updates;
    }
    settled_free_[w] = settled;
  }
  for (std::int64_t k : end_list_) clear_bit(ray_end_, k);
  stats.occupied_updates = occupied_list_.size();
  stats.free_updates = free_updates;
  return stats;
}

}  // namespace porter::mapping
