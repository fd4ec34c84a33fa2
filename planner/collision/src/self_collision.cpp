#include "porter/planner/collision/self_collision.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "porter/planner/collision/robot_kernels.hpp"

namespace porter::planner {

namespace {
constexpr double kSqrt3 = 1.7320508075688772;
constexpr double kGridMargin_m = 0.05;
}  // namespace

SelfCollisionChecker::SelfCollisionChecker(const RobotModel& model, const SelfCollisionSettings& settings)
    : settings_(settings), radii_(compute_chain_radii(model)) {
  if (!(settings.sample_spacing_m > 0.0))
    throw std::invalid_argument("SelfCollisionChecker: sample_spacing_m must be > 0");
  const double s = settings.sample_spacing_m;
  const double thr = 0.5 * kSqrt3 * s;
  // Float32 poses and points: grow the threshold by 0.05 mm so rounding never hides a contact.
  threshold_m_ = static_cast<float>(thr) + 5e-5f;
  std::array<double, kNumLinks> volume{};  // sum of shape bounding-box volumes: sample-count proxy
  for (int k = 0; k < kNumLinks; ++k) {
    const auto i = static_cast<std::size_t>(k);
    links_[i] = LinkDistance(model.links[i].shapes);
    sphere_centre_[i] = model.links[i].bounding_center.cast<float>();
    sphere_radius_[i] = static_cast<float>(model.links[i].bounding_radius_m) + 1e-5f;
    for (const auto& sh : model.links[i].shapes) volume[i] += shape_bounds(sh).volume();
  }
  // Rasters of every link that takes part in a non-allowed pair (proofs and run-time checks).
  for (int a = 0; a < kNumLinks; ++a)
    for (int b = a + 1; b < kNumLinks; ++b) {
      if (model.allowed_collisions[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)]) continue;
      for (int k : {a, b}) {
        const auto i = static_cast<std::size_t>(k);
        if (!links_[i].empty() && grids_[i].bytes() == 0) {
          grids_[i] = DistanceGrid(model.links[i].shapes, s, kGridMargin_m);
          boxes_[i] = BoxUnionBound(model.links[i].shapes);
        }
      }
    }
  std::array<bool, kNumLinks> need_samples{};
  for (int a = 0; a < kNumLinks; ++a)
    for (int b = a + 1; b < kNumLinks; ++b) {
      PairStatus& st = status_[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)];
      const bool allowed = model.allowed_collisions[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] ||
                           links_[static_cast<std::size_t>(a)].empty() || links_[static_cast<std::size_t>(b)].empty();
      if (allowed) {
        st = PairStatus::kAllowed;
      } else if (settings.prove_pairs && prove_separated(model, a, b)) {
        st = PairStatus::kProvenFree;
      } else {
        st = PairStatus::kChecked;
        // Sample the link with the smaller volume, look the other up in its distance grid.
        const bool sample_a = volume[static_cast<std::size_t>(a)] < volume[static_cast<std::size_t>(b)];
        const int g = sample_a ? b : a, smp = sample_a ? a : b;
        pairs_.push_back({g, smp});
        need_samples[static_cast<std::size_t>(smp)] = true;
      }
      status_[static_cast<std::size_t>(b)][static_cast<std::size_t>(a)] = st;
    }
  for (int k = 0; k < kNumLinks; ++k)
    status_[static_cast<std::size_t>(k)][static_cast<std::size_t>(k)] = PairStatus::kAllowed;
  // Payload pairs first (most likely to touch when they do), then from the far end of the chain.
  std::stable_sort(pairs_.begin(), pairs_.end(), [](const auto& p, const auto& q) {
    const int pb = std::max(p[0], p[1]), qb = std::max(q[0], q[1]);
    return pb != qb ? pb > qb : std::min(p[0], p[1]) < std::min(q[0], q[1]);
  });
  for (int k = 0; k < kNumLinks; ++k) {
    const auto i = static_cast<std::size_t>(k);
    samples_.add_tree(need_samples[i] ? grids_[i].occupied_centres() : std::vector<Eigen::Vector3f>{});
  }
  static_assert(kNumLinks == 8, "check() holds one link per lane");
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    if (p % 8 == 0) {
      PairLanes lanes;
      for (int i = 0; i < 8; ++i) {
        lanes.a[i] = lanes.b[i] = 0;
        lanes.reach2[i] = -1.f;
      }
      pair_lanes_.push_back(lanes);
    }
    const auto& pr = pairs_[p];
    const float reach = sphere_radius_[static_cast<std::size_t>(pr[0])] +
                        sphere_radius_[static_cast<std::size_t>(pr[1])] + threshold_m_;
    PairLanes& lanes = pair_lanes_.back();
    lanes.a[p % 8] = pr[0];
    lanes.b[p % 8] = pr[1];
    lanes.reach2[p % 8] = reach * reach;
  }
  static_assert(kNumLinks * (kNumLinks - 1) / 2 <= 32, "check() keeps one bit per pair");
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const int a = pairs_[p][0], b = pairs_[p][1];
    RootGroup* group = nullptr;
    for (RootGroup& g : root_groups_)
      if (g.a == a && g.lane_bits != 0xffu) group = &g;
    if (group == nullptr) {
      group = &root_groups_.emplace_back();
      group->a = a;
      for (int i = 0; i < 8; ++i) {
        group->b[i] = group->pair[i] = 0;
        group->need[i] = 0.f;
      }
    }
    const int lane = __builtin_popcount(group->lane_bits);
    group->b[lane] = b;
    group->need[lane] = samples_.root(b).radius_m + threshold_m_;
    group->pair[lane] = static_cast<std::int32_t>(p);
    group->lane_bits |= 1u << lane;
    group->pair_bits |= 1u << p;
    if (std::find(sampled_links_.begin(), sampled_links_.end(), b) == sampled_links_.end()) sampled_links_.push_back(b);
  }
}

CollisionResult SelfCollisionChecker::pair_result(std::size_t p) const {
  CollisionResult r;
  r.in_collision = true;
  r.link = std::min(pairs_[p][0], pairs_[p][1]);
  r.other_link = std::max(pairs_[p][0], pairs_[p][1]);
  return r;
}

// Pair p's sample tree (link b) below its root, moved into a's frame by T_a_b, against a's grid;
// then the exact distance for points the grid does not clear. Inlined into both callers, so it
// runs in their instruction set.
PORTER_SIMD_INLINE bool SelfCollisionChecker::pair_hit(std::size_t p, const Pose4f& T_a_b_4) const {
  const auto a = static_cast<std::size_t>(pairs_[p][0]), b = static_cast<std::size_t>(pairs_[p][1]);
  const float thr = threshold_m_;
  const v8f thr8 = v8f_splat(thr);
  const PoseLanes T_a_b = PoseLanes::splat(T_a_b_4);
  const DistanceGrid& grid = grids_[a];
  const BoxUnionBound& boxes = boxes_[a];
  const LinkDistance& la = links_[a];
  return wide_tree_any(
      samples_, static_cast<int>(b),
      [&](const WideNode& n) PORTER_SIMD_LAMBDA {
        v8f x, y, z;
        T_a_b.apply(v8f_load(n.cx), v8f_load(n.cy), v8f_load(n.cz), &x, &y, &z);
        const v8f need = v8f_load(n.r) + thr8;
        std::uint32_t open = ~grid.clear_of8(x, y, z, need) & n.used;
        if (open != 0) open &= ~boxes.clear_of8(x, y, z, need);
        return open;
      },
      [&](const PointBlock& blk) PORTER_SIMD_LAMBDA {
        v8f x, y, z;
        T_a_b.apply(v8f_load(blk.x), v8f_load(blk.y), v8f_load(blk.z), &x, &y, &z);
        std::uint32_t m = ~grid.clear_of8(x, y, z, thr8) & 0xffu;
        while (m != 0) {
          const int i = __builtin_ctz(m);
          m &= m - 1;
          if (la.within(Eigen::Vector3f(x[i], y[i], z[i]), thr)) return true;
        }
        return false;
      });
}

PORTER_KERNEL_CLONES CollisionResult SelfCollisionChecker::check(const ArmPoses& poses) const {
  CollisionResult result;
  // 1. Bounding spheres of the links in the base frame (lane k = link k), eight pairs per test:
  //    bit p of `close` = pair p's spheres are within the threshold.
  v4f rows[8];
  for (std::size_t k = 0; k < static_cast<std::size_t>(kNumLinks); ++k)
    rows[k] = poses.T_B_L[k].apply(sphere_centre_[k].x(), sphere_centre_[k].y(), sphere_centre_[k].z());
  std::uint32_t close = 0;
  {
    v8f Cx, Cy, Cz, unused;
    transpose8x4(rows, &Cx, &Cy, &Cz, &unused);
    for (std::size_t chunk = 0; chunk < pair_lanes_.size(); ++chunk) {
      const PairLanes& lanes = pair_lanes_[chunk];
      v8i ia, ib;
      std::memcpy(&ia, lanes.a, sizeof(ia));
      std::memcpy(&ib, lanes.b, sizeof(ib));
      const v8f dx = __builtin_shuffle(Cx, ia) - __builtin_shuffle(Cx, ib);
      const v8f dy = __builtin_shuffle(Cy, ia) - __builtin_shuffle(Cy, ib);
      const v8f dz = __builtin_shuffle(Cz, ia) - __builtin_shuffle(Cz, ib);
      close |= (~lane_mask(dx * dx + dy * dy + dz * dz > v8f_load(lanes.reach2)) & 0xffu) << (8 * chunk);
    }
  }
  if (close == 0) return result;
  // 2. Root spheres of the sample trees, moved into the grid link's frame, eight pairs of one
  //    grid link per test: bit p of `open` = pair p's root sphere is not proven clear.
  for (v4f& r : rows) r = v4f{};
  for (int k : sampled_links_) {
    const WideTreeRoot& root = samples_.root(k);
    rows[static_cast<std::size_t>(k)] = poses.T_B_L[static_cast<std::size_t>(k)].apply(root.cx, root.cy, root.cz);
  }
  std::array<Pose4f, kNumLinks> T_L_B;  // inverses of the grid links' poses, set per group
  std::uint32_t open = 0;
  {
    v8f Rx, Ry, Rz, unused;
    transpose8x4(rows, &Rx, &Ry, &Rz, &unused);
    for (const RootGroup& g : root_groups_) {
      if ((close & g.pair_bits) == 0) continue;
      v8i ib;
      std::memcpy(&ib, g.b, sizeof(ib));
      v8f x = __builtin_shuffle(Rx, ib), y = __builtin_shuffle(Ry, ib), z = __builtin_shuffle(Rz, ib);
      const auto a = static_cast<std::size_t>(g.a);
      if (a != 0) {  // T_B_L[0] is the identity
        T_L_B[a] = poses.T_B_L[a].inverse();
        PoseLanes::splat(T_L_B[a]).apply(x, y, z, &x, &y, &z);
      }
      const v8f need = v8f_load(g.need);
      std::uint32_t m = g.lane_bits & ~boxes_[a].clear_of8(x, y, z, need);
      if (m != 0) m &= ~grids_[a].clear_of8(x, y, z, need);
      while (m != 0) {
        open |= 1u << g.pair[__builtin_ctz(m)];
        m &= m - 1;
      }
    }
  }
  open &= close;
  // 3. The remaining pairs in pair order: b's sample tree below the root against a's grid, then
  //    the exact distance for points the grid does not clear.
  while (open != 0) {
    const auto p = static_cast<std::size_t>(__builtin_ctz(open));
    open &= open - 1;
    const auto a = static_cast<std::size_t>(pairs_[p][0]), b = static_cast<std::size_t>(pairs_[p][1]);
    if (pair_hit(p, a == 0 ? poses.T_B_L[b] : T_L_B[a] * poses.T_B_L[b])) return pair_result(p);
  }
  return result;
}

PORTER_KERNEL_CLONES void SelfCollisionChecker::check_lanes(const ArmPoseLanes& poses, std::uint32_t lanes,
                                                            CollisionResult* results) const {
  // 1. Bounding spheres: close[p] = lanes in which pair p's spheres are within the threshold.
  std::array<v8f, kNumLinks> Cx, Cy, Cz;
  for (std::size_t k = 0; k < static_cast<std::size_t>(kNumLinks); ++k)
    poses.T_B_L[k].apply(v8f_splat(sphere_centre_[k].x()), v8f_splat(sphere_centre_[k].y()),
                         v8f_splat(sphere_centre_[k].z()), &Cx[k], &Cy[k], &Cz[k]);
  std::array<std::uint32_t, 8> open{};  // per lane: bit p = pair p's root sphere is not proven clear
  std::array<bool, kNumLinks> have_root{};
  std::array<v8f, kNumLinks> Rx, Ry, Rz;
  const float thr = threshold_m_;
  for (std::size_t p = 0; p < pairs_.size(); ++p) {
    const auto a = static_cast<std::size_t>(pairs_[p][0]), b = static_cast<std::size_t>(pairs_[p][1]);
    const v8f dx = Cx[a] - Cx[b], dy = Cy[a] - Cy[b], dz = Cz[a] - Cz[b];
    const std::uint32_t close =
        ~lane_mask(dx * dx + dy * dy + dz * dz > v8f_splat(pair_lanes_[p / 8].reach2[p % 8])) & lanes;
    if (close == 0) continue;
    // 2. b's root sphere in a's frame against a's grid.
    const WideTreeRoot& root = samples_.root(static_cast<int>(b));
    if (!have_root[b]) {
      poses.T_B_L[b].apply(v8f_splat(root.cx), v8f_splat(root.cy), v8f_splat(root.cz), &Rx[b], &Ry[b], &Rz[b]);
      have_root[b] = true;
    }
    v8f x = Rx[b], y = Ry[b], z = Rz[b];
    if (a != 0) poses.T_B_L[a].apply_inverse(x, y, z, &x, &y, &z);  // T_B_L[0] is the identity
    // The boxes first (no memory to read; they clear more root spheres than the grid, whose
    // bound outside its box is the distance to that box), then the grid for the lanes left
    // unless the sphere is larger than the grid can ever prove.
    const float need = root.radius_m + thr;
    std::uint32_t m = close & ~boxes_[a].clear_of8(x, y, z, v8f_splat(need));
    if (m != 0 && need < grids_[a].cap_m()) m &= ~grids_[a].clear_of8(x, y, z, v8f_splat(need));
    while (m != 0) {
      open[static_cast<std::size_t>(__builtin_ctz(m))] |= 1u << p;
      m &= m - 1;
    }
  }
  // 3. Per lane, the remaining pairs in pair order, as in check().
  for (std::uint32_t l = lanes; l != 0; l &= l - 1) {
    const int i = __builtin_ctz(l);
    std::uint32_t o = open[static_cast<std::size_t>(i)];
    results[i] = CollisionResult{};
    while (o != 0) {
      const auto p = static_cast<std::size_t>(__builtin_ctz(o));
      o &= o - 1;
      const auto a = static_cast<std::size_t>(pairs_[p][0]), b = static_cast<std::size_t>(pairs_[p][1]);
      const Pose4f T_B_b = poses.T_B_L[b].lane(i);
      if (pair_hit(p, a == 0 ? T_B_b : poses.T_B_L[a].lane(i).inverse() * T_B_b)) {
        results[i] = pair_result(p);
        break;
      }
    }
  }
}

std::size_t SelfCollisionChecker::bytes() const {
  std::size_t n = samples_.bytes();
  for (const auto& g : grids_) n += g.bytes();
  return n;
}

}  // namespace porter::planner
