#include "porter/frontend/grid_heuristic.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace porter::frontend {

namespace {

bool inside_base(const RobotModel& model, const Eigen::Vector3d& p_B) {
  for (const CollisionShape& s : model.links[0].shapes) {
    if (shape_contains(s, p_B)) return true;
  }
  return false;
}

double disc_radius_at(const RobotModel& model, double z_m) {
  constexpr int kAngles = 64;
  constexpr double kStep = 0.005;
  double r_ok = -1.0;
  for (double r = 0.0; r < 5.0; r += kStep) {
    const int n = r == 0.0 ? 1 : kAngles;
    for (int k = 0; k < n; ++k) {
      const double a = 2.0 * M_PI * k / n;
      if (!inside_base(model, Eigen::Vector3d(r * std::cos(a), r * std::sin(a), z_m))) return r_ok;
    }
    r_ok = r;
  }
  return r_ok;
}

}  // namespace

InscribedDisc base_inscribed_disc(const RobotModel& model) {
  InscribedDisc best;
  const Eigen::AlignedBox3d& b = model.links[0].bounds;
  if (b.isEmpty()) return best;
  constexpr int kLevels = 17;
  for (int i = 1; i < kLevels; ++i) {
    const double z = b.min().z() + (b.max().z() - b.min().z()) * i / kLevels;
    const double r = disc_radius_at(model, z);
    if (r > best.radius_m) best = {r, z};
  }
  return best;
}

void GridHeuristic::build(const OccupancyGrid& occ, const InscribedDisc& disc, double resolution_m) {
  res_ = resolution_m;
  const Eigen::AlignedBox3d bw = occ.bounds_W();
  origin_ = bw.min().head<2>();
  const Eigen::Vector2d ext = bw.max().head<2>() - origin_;
  nx_ = std::max(1, static_cast<int>(std::ceil(ext.x() / res_ - 1e-9)));
  ny_ = std::max(1, static_cast<int>(std::ceil(ext.y() / res_ - 1e-9)));
  blocked_.assign(static_cast<std::size_t>(nx_) * ny_, 0);
  dist_.assign(blocked_.size(), std::numeric_limits<float>::infinity());

  const double half_diag = 0.5 * std::sqrt(2.0) * res_;
  const double reach = disc.radius_m - half_diag;  // disc covers the point for every base in the cell
  if (reach <= 0.0) return;

  // Cells too close to the horizontal boundary: the disc leaves the map for every base inside.
  for (int iy = 0; iy < ny_; ++iy) {
    for (int ix = 0; ix < nx_; ++ix) {
      const double cx = origin_.x() + (ix + 0.5) * res_, cy = origin_.y() + (iy + 0.5) * res_;
      const double d = std::min({cx - bw.min().x(), bw.max().x() - cx, cy - bw.min().y(), bw.max().y() - cy});
      if (d < reach) blocked_[ix + static_cast<std::size_t>(nx_) * iy] = 1;
    }
  }
  const double vres = occ.resolution_m();
  const int iz = static_cast<int>(std::floor((disc.z_m - occ.origin_W().z()) / vres));
  if (iz < 0 || iz >= occ.dims().z()) return;
  const int span = static_cast<int>(std::ceil(reach / res_)) + 1;
  for (int vy = 0; vy < occ.dims().y(); ++vy) {
    for (int vx = 0; vx < occ.dims().x(); ++vx) {
      if (!occ.occupied(vx, vy, iz)) continue;
      const Eigen::Vector3d c = occ.voxel_center_W(vx, vy, iz);
      const int cx0 = static_cast<int>(std::floor((c.x() - origin_.x()) / res_));
      const int cy0 = static_cast<int>(std::floor((c.y() - origin_.y()) / res_));
      for (int iy = std::max(0, cy0 - span); iy <= std::min(ny_ - 1, cy0 + span); ++iy) {
        for (int ix = std::max(0, cx0 - span); ix <= std::min(nx_ - 1, cx0 + span); ++ix) {
          const double dx = origin_.x() + (ix + 0.5) * res_ - c.x();
          const double dy = origin_.y() + (iy + 0.5) * res_ - c.y();
          if (dx * dx + dy * dy <= reach * reach) blocked_[ix + static_cast<std::size_t>(nx_) * iy] = 1;
        }
      }
    }
  }
}

int GridHeuristic::cell_index(double x_m, double y_m) const {
  const double fx = (x_m - origin_.x()) / res_, fy = (y_m - origin_.y()) / res_;
  if (!(fx >= 0.0 && fy >= 0.0 && fx < nx_ && fy < ny_)) return -1;
  return static_cast<int>(fx) + nx_ * static_cast<int>(fy);
}

bool GridHeuristic::blocked(double x_m, double y_m) const {
  const int c = cell_index(x_m, y_m);
  return c < 0 || blocked_[static_cast<std::size_t>(c)] != 0;
}

std::int64_t GridHeuristic::blocked_count() const {
  return std::count(blocked_.begin(), blocked_.end(), std::uint8_t{1});
}

bool GridHeuristic::set_goal(double x_m, double y_m) {
  std::fill(dist_.begin(), dist_.end(), std::numeric_limits<float>::infinity());
  const int g = cell_index(x_m, y_m);
  if (g < 0) return false;
  using Item = std::pair<float, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist_[static_cast<std::size_t>(g)] = 0.0f;
  open.push({0.0f, g});
  const float straight = static_cast<float>(res_), diag = static_cast<float>(res_ * std::sqrt(2.0));
  static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const auto [d, c] = open.top();
    open.pop();
    if (d > dist_[static_cast<std::size_t>(c)]) continue;
    const int cx = c % nx_, cy = c / nx_;
    for (int k = 0; k < 8; ++k) {
      const int x = cx + kDx[k], y = cy + kDy[k];
      if (x < 0 || y < 0 || x >= nx_ || y >= ny_) continue;
      const int n = x + nx_ * y;
      if (blocked_[static_cast<std::size_t>(n)]) continue;
      const float nd = d + (k < 4 ? straight : diag);
      if (nd < dist_[static_cast<std::size_t>(n)]) {
        dist_[static_cast<std::size_t>(n)] = nd;
        open.push({nd, n});
      }
    }
  }
  return true;
}

double GridHeuristic::distance(double x_m, double y_m) const {
  const int c = cell_index(x_m, y_m);
  if (c < 0) return std::numeric_limits<double>::infinity();
  const float d = dist_[static_cast<std::size_t>(c)];
  if (!std::isfinite(d)) return std::numeric_limits<double>::infinity();
  return std::max(0.0, static_cast<double>(d) - std::sqrt(2.0) * res_);
}

}  // namespace porter::frontend
