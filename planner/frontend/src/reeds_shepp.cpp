#include "porter/frontend/reeds_shepp.hpp"
#include "porter/planner/angle.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <ompl/base/spaces/ReedsSheppStateSpace.h>

namespace porter::frontend {

namespace ob = ompl::base;

int RsPath::cusps() const {
  int n = 0;
  int last = 0;
  for (int i = 0; i < num_segments; ++i) {
    if (segments[i].length_m == 0.0) continue;
    const int eta = segments[i].length_m > 0.0 ? 1 : -1;
    if (last != 0 && eta != last) ++n;
    last = eta;
  }
  return n;
}

BasePose drive_arc(const BasePose& from, double curvature_1pm, double length_m) {
  BasePose p = from;
  const double dyaw = curvature_1pm * length_m;
  if (std::abs(dyaw) < 1e-9) {
    p.x_m += length_m * std::cos(from.yaw_rad);
    p.y_m += length_m * std::sin(from.yaw_rad);
  } else {
    const double r = 1.0 / curvature_1pm;
    p.x_m += r * (std::sin(from.yaw_rad + dyaw) - std::sin(from.yaw_rad));
    p.y_m += r * (-std::cos(from.yaw_rad + dyaw) + std::cos(from.yaw_rad));
  }
  p.yaw_rad = planner::wrap_angle_rad(from.yaw_rad + dyaw);
  return p;
}

struct ReedsShepp::Impl {
  explicit Impl(double r) : space(r) {
    a = space.allocState()->as<ob::SE2StateSpace::StateType>();
    b = space.allocState()->as<ob::SE2StateSpace::StateType>();
  }
  ~Impl() {
    space.freeState(a);
    space.freeState(b);
  }
  ob::ReedsSheppStateSpace space;
  ob::SE2StateSpace::StateType* a;
  ob::SE2StateSpace::StateType* b;
};

ReedsShepp::ReedsShepp(double turning_radius_m)
    : radius_m_(turning_radius_m), impl_(std::make_unique<Impl>(turning_radius_m)) {}

ReedsShepp::~ReedsShepp() = default;

RsPath ReedsShepp::shortest(const BasePose& from, const BasePose& to) const {
  RsPath out;
  out.radius_m = radius_m_;
  if (!std::isfinite(from.x_m + from.y_m + from.yaw_rad + to.x_m + to.y_m + to.yaw_rad)) {
    out.length_m = std::numeric_limits<double>::infinity();
    return out;
  }
  impl_->a->setXY(from.x_m, from.y_m);
  impl_->a->setYaw(from.yaw_rad);
  impl_->b->setXY(to.x_m, to.y_m);
  impl_->b->setYaw(to.yaw_rad);
  const ob::ReedsSheppStateSpace::ReedsSheppPath p = impl_->space.reedsShepp(impl_->a, impl_->b);
  // OMPL lengths are in units of the turning radius, signed by direction.
  for (int i = 0; i < 5; ++i) {
    const auto type = p.type_[i];
    if (type == ob::ReedsSheppStateSpace::RS_NOP) break;
    if (p.length_[i] == 0.0) continue;
    RsSegment seg;
    seg.kind = type == ob::ReedsSheppStateSpace::RS_LEFT    ? RsSegment::Kind::kLeft
               : type == ob::ReedsSheppStateSpace::RS_RIGHT ? RsSegment::Kind::kRight
                                                            : RsSegment::Kind::kStraight;
    seg.length_m = p.length_[i] * radius_m_;
    out.segments[out.num_segments++] = seg;
    out.length_m += std::abs(seg.length_m);
  }
  return out;
}

double ReedsShepp::distance(const BasePose& from, const BasePose& to) const {
  return shortest(from, to).length_m;
}

namespace {

double curvature_of(const RsSegment& seg, double radius_m) {
  switch (seg.kind) {
    case RsSegment::Kind::kLeft: return 1.0 / radius_m;
    case RsSegment::Kind::kRight: return -1.0 / radius_m;
    case RsSegment::Kind::kStraight: return 0.0;
  }
  return 0.0;
}

}  // namespace

BasePose rs_pose_at(const BasePose& from, const RsPath& path, double s_m, int* eta) {
  BasePose p = from;
  double remaining = std::max(0.0, s_m);
  int last_eta = 1;
  for (int i = 0; i < path.num_segments; ++i) {
    const RsSegment& seg = path.segments[i];
    const double len = std::abs(seg.length_m);
    last_eta = seg.length_m >= 0.0 ? 1 : -1;
    const double d = std::min(remaining, len);
    p = drive_arc(p, curvature_of(seg, path.radius_m), last_eta * d);
    remaining -= d;
    if (remaining <= 0.0) break;
  }
  if (eta) *eta = last_eta;
  return p;
}

void sample_rs_path(const BasePose& from, const RsPath& path, double max_step_m,
                    std::vector<BaseSample>* out) {
  const int first_eta = path.num_segments > 0 && path.segments[0].length_m < 0.0 ? -1 : 1;
  out->push_back({from, first_eta});
  BasePose p = from;
  for (int i = 0; i < path.num_segments; ++i) {
    const RsSegment& seg = path.segments[i];
    const int eta = seg.length_m >= 0.0 ? 1 : -1;
    const double len = std::abs(seg.length_m);
    const int n = std::max(1, static_cast<int>(std::ceil(len / max_step_m - 1e-9)));
    const double kappa = curvature_of(seg, path.radius_m);
    for (int k = 1; k <= n; ++k) {
      out->push_back({drive_arc(p, kappa, eta * len * k / n), eta});
    }
    p = out->back().pose;
  }
}

}  // namespace porter::frontend
