#include "porter/mapping/self_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "porter/core/geometry.hpp"
#include "porter/core/kinematics.hpp"

namespace porter::mapping {

double SelfFilter::link_distance(int link, const Eigen::Vector3d& p_L) const {
  double d = std::numeric_limits<double>::infinity();
  for (const CollisionShape& s : robot_.links[static_cast<std::size_t>(link)].shapes) {
    d = std::min(d, shape_signed_distance(s, p_L));
  }
  return d;
}

SelfFilter::SelfFilter(const RobotModel& robot, const SelfFilterParams& params)
    : robot_(robot), params_(params) {
  const double cell = params_.cell_m;
  const double half_diag = 0.5 * std::sqrt(3.0) * cell;
  const double m = params_.margin_m;
  for (int l = 0; l < kNumLinks; ++l) {
    const Link& link = robot_.links[static_cast<std::size_t>(l)];
    LinkGrid& g = grids_[static_cast<std::size_t>(l)];
    if (link.shapes.empty()) continue;
    g.center_L = link.bounding_center;
    g.radius_m = link.bounding_radius_m + m;
    Eigen::AlignedBox3d box = link.bounds;
    box.min().array() -= m + cell;
    box.max().array() += m + cell;
    g.origin_L = box.min();
    g.dims = ((box.max() - box.min()) / cell).array().ceil().cast<int>().max(1).matrix();
    g.cells.assign(static_cast<std::size_t>(g.dims.x()) * g.dims.y() * g.dims.z(), kOutside);
    // Bounds of each shape grown by the band: a cell centre outside them is outside that shape.
    std::vector<Eigen::AlignedBox3d> shape_boxes;
    for (const CollisionShape& s : link.shapes) {
      Eigen::AlignedBox3d b = shape_bounds(s);
      b.min().array() -= m + half_diag;
      b.max().array() += m + half_diag;
      shape_boxes.push_back(b);
    }
    std::size_t k = 0;
    for (int z = 0; z < g.dims.z(); ++z)
      for (int y = 0; y < g.dims.y(); ++y)
        for (int x = 0; x < g.dims.x(); ++x, ++k) {
          const Eigen::Vector3d c = g.origin_L + (Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(0.5)) * cell;
          double d = std::numeric_limits<double>::infinity();
          for (std::size_t i = 0; i < link.shapes.size(); ++i) {
            if (!shape_boxes[i].contains(c)) continue;
            d = std::min(d, shape_signed_distance(link.shapes[i], c));
          }
          g.cells[k] = d <= m - half_diag ? kInside : (d > m + half_diag ? kOutside : kBoundary);
        }
  }
  set_arm(JointVector::Zero());
}

void SelfFilter::set_arm(const JointVector& q_rad) {
  std::array<Eigen::Isometry3d, kNumLinks> T_B_L;
  arm_forward_kinematics(robot_, q_rad, T_B_L);
  for (int l = 0; l < kNumLinks; ++l) {
    T_L_B_[static_cast<std::size_t>(l)] = T_B_L[static_cast<std::size_t>(l)].inverse(Eigen::Isometry);
    center_B_[static_cast<std::size_t>(l)] = T_B_L[static_cast<std::size_t>(l)] * grids_[static_cast<std::size_t>(l)].center_L;
  }
}

bool SelfFilter::contains(const Eigen::Vector3d& p_B) const {
  for (int l = 0; l < kNumLinks; ++l) {
    const LinkGrid& g = grids_[static_cast<std::size_t>(l)];
    if (g.radius_m < 0.0 || (p_B - center_B_[static_cast<std::size_t>(l)]).squaredNorm() > g.radius_m * g.radius_m) continue;
    const Eigen::Vector3d p_L = T_L_B_[static_cast<std::size_t>(l)] * p_B;
    const Eigen::Vector3d f = (p_L - g.origin_L) / params_.cell_m;
    const int x = static_cast<int>(std::floor(f.x())), y = static_cast<int>(std::floor(f.y())),
              z = static_cast<int>(std::floor(f.z()));
    if (x < 0 || y < 0 || z < 0 || x >= g.dims.x() || y >= g.dims.y() || z >= g.dims.z()) continue;
    const std::uint8_t c = g.cells[static_cast<std::size_t>(x + g.dims.x() * (y + static_cast<std::int64_t>(g.dims.y()) * z))];
    if (c == kInside) return true;
    if (c == kBoundary) {
      ++exact_tests_;
      if (link_distance(l, p_L) <= params_.margin_m) return true;
    }
  }
  return false;
}

double SelfFilter::signed_distance(const Eigen::Vector3d& p_B) const {
  double d = std::numeric_limits<double>::infinity();
  for (int l = 0; l < kNumLinks; ++l) {
    if (grids_[static_cast<std::size_t>(l)].radius_m < 0.0) continue;
    d = std::min(d, link_distance(l, T_L_B_[static_cast<std::size_t>(l)] * p_B));
  }
  return d;
}

std::int64_t SelfFilter::cells() const {
  std::int64_t n = 0;
  for (const LinkGrid& g : grids_) n += static_cast<std::int64_t>(g.cells.size());
  return n;
}

std::int64_t SelfFilter::boundary_cells() const {
  std::int64_t n = 0;
  for (const LinkGrid& g : grids_) n += std::count(g.cells.begin(), g.cells.end(), kBoundary);
  return n;
}

}  // namespace porter::mapping
