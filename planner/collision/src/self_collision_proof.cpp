// Build-time proofs that a pair of links can never touch (self_collision.hpp, step 1).
#include <algorithm>
#include <cmath>
#include <deque>

#include "porter/planner/collision/self_collision.hpp"

namespace porter::planner {

namespace {

constexpr double kSqrt3 = 1.7320508075688772;

enum class Separation { kFar, kClose, kOverlap };

/// Motion of b relative to a over a joint box: b's points move at most
///   sum_i hw_i * (distance to joint i's axis + excursion) <= sum_i hw_i (|p - o_i| + 2 M)
/// where hw_i is the box half-width of joint i, o_i its origin at the box centre and M the
/// global bound sum_i hw_i R_i (R_i: chain radius of b from joint i). Points near the axes move
/// little, which is what lets wrist pairs be proven.
struct Motion {
  int n = 0;
  std::array<double, 2> half_width{};
  std::array<Eigen::Vector3d, 2> origin_a{};  ///< joint origins in a's frame at the box centre
  double global = 0.0;
  double at(const Eigen::Vector3d& c, double rho) const {
    double m = 0.0;
    for (int i = 0; i < n; ++i)
      m += half_width[static_cast<std::size_t>(i)] *
           ((c - origin_a[static_cast<std::size_t>(i)]).norm() + rho + 2.0 * global);
    return std::min(m, global);
  }
};

struct OctreeProof {
  const LinkDistance& a;
  const LinkDistance& b;
  const DistanceGrid& grid_a;
  const DistanceGrid& grid_b;
  Eigen::Isometry3d T_b_a;
  const Motion& motion;
  double min_half;
  long evaluations_left;

  Separation cell(const Eigen::Vector3d& c, double half) {
    if (--evaluations_left < 0) return Separation::kClose;
    const double rho = half * kSqrt3;
    const double m = motion.at(c, rho);
    // Cheap lower bounds first (rasterized distance grids), exact distances only when needed.
    const Eigen::Vector3d cb = T_b_a * c;
    if (grid_a.lower_bound(c.cast<float>()) - 1e-5 > rho + m) return Separation::kFar;
    if (grid_b.lower_bound(cb.cast<float>()) - 1e-5 > rho) return Separation::kFar;
    const double da = a.signed_distance(c);
    if (da > rho + m) return Separation::kFar;  // b's points here never reach a
    const double db = b.signed_distance(cb);
    if (db > rho) return Separation::kFar;  // no point of b in the cell
    if (da <= 0.0 && db <= 0.0) return Separation::kOverlap;
    if (half < min_half) return Separation::kClose;
    const double q = 0.5 * half;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d cc = c + q * Eigen::Vector3d((k & 1) ? 1 : -1, (k & 2) ? 1 : -1, (k & 4) ? 1 : -1);
      const Separation s = cell(cc, q);
      if (s != Separation::kFar) return s;  // overlap ends the proof; close splits the joint box
    }
    return Separation::kFar;
  }
};

/// kFar when no point of b (placed by T_a_b at the box centre) comes within the motion bound of a.
Separation separation(const LinkDistance& a, const LinkDistance& b, const DistanceGrid& grid_a,
                      const DistanceGrid& grid_b, const Eigen::Isometry3d& T_a_b, const Motion& motion,
                      double min_half) {
  Eigen::AlignedBox3d bb;
  bb.setEmpty();
  const Eigen::AlignedBox3d& lb = b.bounds();
  for (int k = 0; k < 8; ++k)
    bb.extend(T_a_b * Eigen::Vector3d((k & 1) ? lb.max().x() : lb.min().x(), (k & 2) ? lb.max().y() : lb.min().y(),
                                      (k & 4) ? lb.max().z() : lb.min().z()));
  const double margin = motion.global;
  const Eigen::AlignedBox3d ga(a.bounds().min().array() - margin, a.bounds().max().array() + margin);
  const Eigen::AlignedBox3d region = ga.intersection(bb);
  if (region.isEmpty()) return Separation::kFar;
  OctreeProof proof{a, b, grid_a, grid_b, T_a_b.inverse(Eigen::Isometry), motion, min_half, 400000};
  return proof.cell(region.center(), 0.5 * region.sizes().maxCoeff());
}

}  // namespace

bool SelfCollisionChecker::prove_separated(const RobotModel& model, int a, int b) const {
  const int j_end = std::min(b, kNumArmJoints);
  const int m = std::max(0, j_end - a);
  if (m > 2) return false;
  // offsets[l]: distance between frame origins l-1 and l; chain radius from joint i to link b.
  std::array<double, kNumLinks> offset{};
  for (int l = 1; l <= kNumArmJoints; ++l)
    offset[static_cast<std::size_t>(l)] =
        model.joints[static_cast<std::size_t>(l - 1)].T_parent_joint.translation().norm();
  offset[kEndEffectorLink] = model.T_L6_EE.translation().norm();
  std::array<double, 2> reach{}, lo{}, hi{};
  for (int k = 0; k < m; ++k) {
    const int i = a + 1 + k;
    double d = radii_.link_radius_m[static_cast<std::size_t>(b)];
    for (int l = i + 1; l <= b; ++l) d += offset[static_cast<std::size_t>(l)];
    reach[static_cast<std::size_t>(k)] = d;
    lo[static_cast<std::size_t>(k)] = model.joints[static_cast<std::size_t>(i - 1)].lower_rad;
    hi[static_cast<std::size_t>(k)] = model.joints[static_cast<std::size_t>(i - 1)].upper_rad;
  }
  // Pose of b in a's frame at joint values q, and the origins of the joints in J (a's frame).
  auto pose = [&](const std::array<double, 2>& q, Motion& motion) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int i = a + 1; i <= j_end; ++i) {
      const ArmJoint& jt = model.joints[static_cast<std::size_t>(i - 1)];
      T = T * jt.T_parent_joint;
      motion.origin_a[static_cast<std::size_t>(i - a - 1)] = T.translation();
      T = T * Eigen::AngleAxisd(q[static_cast<std::size_t>(i - a - 1)], jt.axis.normalized());
    }
    if (b == kEndEffectorLink) T = T * model.T_L6_EE;
    return T;
  };
  const LinkDistance& la = links_[static_cast<std::size_t>(a)];
  const LinkDistance& lb = links_[static_cast<std::size_t>(b)];
  struct Box {
    std::array<double, 2> lo, hi;
  };
  std::deque<Box> queue{Box{lo, hi}};
  int examined = 0;
  while (!queue.empty()) {
    if (++examined > settings_.proof_max_boxes) return false;
    const Box box = queue.front();
    queue.pop_front();
    std::array<double, 2> centre{};
    Motion motion;
    motion.n = m;
    int widest = 0;
    double widest_motion = -1.0;
    for (int k = 0; k < m; ++k) {
      const auto s = static_cast<std::size_t>(k);
      centre[s] = 0.5 * (box.lo[s] + box.hi[s]);
      motion.half_width[s] = 0.5 * (box.hi[s] - box.lo[s]);
      const double mk = motion.half_width[s] * reach[s];
      motion.global += mk;
      if (mk > widest_motion) {
        widest_motion = mk;
        widest = k;
      }
    }
    const Eigen::Isometry3d T_a_b = pose(centre, motion);
    const Separation sep = separation(la, lb, grids_[static_cast<std::size_t>(a)], grids_[static_cast<std::size_t>(b)],
                                      T_a_b, motion, settings_.proof_min_cell_m);
    const double motion_bound = motion.global;
    if (sep == Separation::kOverlap) return false;
    if (sep == Separation::kFar) continue;
    if (m == 0 || motion_bound < settings_.proof_min_cell_m) return false;  // touching, or too close to prove
    Box left = box, right = box;
    const auto w = static_cast<std::size_t>(widest);
    left.hi[w] = right.lo[w] = centre[w];
    queue.push_back(left);
    queue.push_back(right);
  }
  return true;
}

}  // namespace porter::planner
