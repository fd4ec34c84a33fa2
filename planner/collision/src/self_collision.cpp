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
        if (!links_[i].empty() && grids_[i].bytes() == 0)
          grids_[i] = DistanceGrid(model.links[i].shapes, s, kGridMargin_m);
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
}

PORTER_KERNEL_CLONES CollisionResult SelfCollisionChecker::check(const ArmPoses& poses) const {
  CollisionResult result;
  const float thr = threshold_m_;
  // Bounding spheres of the links in the base frame, lane k = link k.
  alignas(32) float cx[8], cy[8], cz[8];
  for (std::size_t k = 0; k < static_cast<std::size_t>(kNumLinks); ++k) {
    const v4f c = poses.T_B_L[k].apply(sphere_centre_[k].x(), sphere_centre_[k].y(), sphere_centre_[k].z());
    cx[k] = c[0];
    cy[k] = c[1];
    cz[k] = c[2];
  }
  const v8f Cx = v8f_load(cx), Cy = v8f_load(cy), Cz = v8f_load(cz);
  std::array<Pose4f, kNumLinks> T_L_B;  // inverses, computed when first needed
  std::array<bool, kNumLinks> have_inverse{};
  have_inverse[0] = true;  // T_B_L[0] is the identity
  // Pairs whose bounding spheres are within the threshold, eight pairs per test, in pair order.
  for (std::size_t chunk = 0; chunk < pair_lanes_.size(); ++chunk) {
    const PairLanes& lanes = pair_lanes_[chunk];
    v8i ia, ib;
    std::memcpy(&ia, lanes.a, sizeof(ia));
    std::memcpy(&ib, lanes.b, sizeof(ib));
    const v8f dx = __builtin_shuffle(Cx, ia) - __builtin_shuffle(Cx, ib);
    const v8f dy = __builtin_shuffle(Cy, ia) - __builtin_shuffle(Cy, ib);
    const v8f dz = __builtin_shuffle(Cz, ia) - __builtin_shuffle(Cz, ib);
    std::uint32_t close = ~lane_mask(dx * dx + dy * dy + dz * dz > v8f_load(lanes.reach2)) & 0xffu;
    while (close != 0) {
      const std::size_t p = 8 * chunk + static_cast<std::size_t>(__builtin_ctz(close));
      close &= close - 1;
      const auto& pr = pairs_[p];
      const auto a = static_cast<std::size_t>(pr[0]), b = static_cast<std::size_t>(pr[1]);
      const WideTreeRoot& root = samples_.root(static_cast<int>(b));
      if (!have_inverse[a]) {
        T_L_B[a] = poses.T_B_L[a].inverse();
        have_inverse[a] = true;
      }
      // The root sphere first, without composing the full transform.
      const v4f r_B = poses.T_B_L[b].apply(root.cx, root.cy, root.cz);
      const v4f r_a = a == 0 ? r_B : T_L_B[a].apply(r_B[0], r_B[1], r_B[2]);
      const DistanceGrid& grid = grids_[a];
      if (grid.clear_of(Eigen::Vector3f(r_a[0], r_a[1], r_a[2]), root.radius_m + thr)) continue;
      const Pose8f T_a_b = Pose8f::from(a == 0 ? poses.T_B_L[b] : T_L_B[a] * poses.T_B_L[b]);
      const LinkDistance& la = links_[a];
      const v8f thr8 = v8f_splat(thr);
      const bool hit = wide_tree_any(
          samples_, static_cast<int>(b),
          [&](const WideNode& n) PORTER_SIMD_LAMBDA {
            v8f x, y, z;
            T_a_b.apply(v8f_load(n.cx), v8f_load(n.cy), v8f_load(n.cz), &x, &y, &z);
            return ~grid.clear_of8(x, y, z, v8f_load(n.r) + thr8);
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
      if (hit) {
        result.in_collision = true;
        result.link = std::min(pr[0], pr[1]);
        result.other_link = std::max(pr[0], pr[1]);
        return result;
      }
    }
  }
  return result;
}

std::size_t SelfCollisionChecker::bytes() const {
  std::size_t n = samples_.bytes();
  for (const auto& g : grids_) n += g.bytes();
  return n;
}

}  // namespace porter::planner
