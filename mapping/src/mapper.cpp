#include "porter/mapping/mapper.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "porter/mapping/pcl_filters.hpp"

namespace porter::mapping {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

std::string validate(const MapperParams& p) {
  const RollingMapParams& m = p.map;
  if (!(m.resolution_m > 0.0)) return "map.resolution_m must be > 0";
  if ((m.dims.array() < 2).any()) return "map.dims must be >= 2 per axis";
  if ((m.dims.array() > 16384).any()) return "map.dims must be <= 16384 per axis";
  const auto prob = [](double v) { return v > 0.0 && v < 1.0; };
  if (!prob(m.prob_hit) || m.prob_hit <= 0.5) return "map.prob_hit must be in (0.5, 1)";
  if (!prob(m.prob_miss) || m.prob_miss >= 0.5) return "map.prob_miss must be in (0, 0.5)";
  if (!prob(m.clamp_min) || !prob(m.clamp_max) || m.clamp_min >= m.clamp_max) return "map.clamp_min/max must satisfy 0 < min < max < 1";
  if (!prob(m.occupancy_threshold)) return "map.occupancy_threshold must be in (0, 1)";
  // A shadow longer than a few metres would mark whole rooms behind a person walking by.
  if (!(m.new_surface_shadow_m >= 0.0 && m.new_surface_shadow_m <= 5.0)) return "map.new_surface_shadow_m must be in [0, 5] m";
  if (!(p.recenter_distance_m >= 0.0)) return "recenter_distance_m must be >= 0";
  if (!(p.min_range_m >= 0.0)) return "min_range_m must be >= 0";
  if (!(p.max_range_m > p.min_range_m)) return "max_range_m must be > min_range_m";
  if (!(p.self.margin_m >= 0.0)) return "self_filter.margin_m must be >= 0";
  if (!(p.self.cell_m > 0.0)) return "self_filter.cell_m must be > 0";
  if (!(p.arm_pose_period_s > 0.0)) return "self_filter.arm_pose_period_s must be > 0";
  if (!(p.voxel_grid_leaf_m >= 0.0)) return "voxel_grid_leaf_m must be >= 0";
  if (p.outlier_mean_k < 0) return "outlier_removal.mean_k must be >= 0";
  if (!(p.outlier_stddev_mul > 0.0)) return "outlier_removal.stddev_mul must be > 0";
  return "";
}

Mapper::Mapper(const RobotModel& robot, const MapperParams& params) : params_(params), map_(params.map) {
  set_robot(robot);
}

Mapper::~Mapper() = default;

void Mapper::set_robot(const RobotModel& robot) {
  self_ = params_.self_filter ? std::make_unique<SelfFilter>(robot, params_.self) : nullptr;
}

FilterStats Mapper::filter(const SensorCloud& cloud, const StateBuffer& states, FilteredCloud& out,
                           std::vector<std::uint8_t>* self_removed) {
  const auto t0 = std::chrono::steady_clock::now();
  FilterStats st;
  const std::size_t n = std::min({cloud.x_m.size(), cloud.y_m.size(), cloud.z_m.size(), cloud.time_offset_ns.size()});
  st.points_in = n;
  if (self_removed) self_removed->assign(n, 0);
  out.points_W.clear();
  out.points_W.reserve(n);
  std::int32_t off_min = 0, off_max = 0;
  if (n > 0) {
    const auto [lo, hi] = std::minmax_element(cloud.time_offset_ns.begin(), cloud.time_offset_ns.begin() + static_cast<std::ptrdiff_t>(n));
    off_min = *lo;
    off_max = *hi;
  }
  out.utime_end = cloud.utime + off_max / 1000;
  const std::int64_t period_ns = std::max<std::int64_t>(1, static_cast<std::int64_t>(params_.arm_pose_period_s * 1e9));
  const Eigen::Matrix3d R_B_S = params_.T_B_S.linear();
  const Eigen::Vector3d t_B_S = params_.T_B_S.translation();
  const double min_range2 = params_.min_range_m * params_.min_range_m;
  std::int64_t arm_slot = std::numeric_limits<std::int64_t>::min();
  RobotConfiguration c;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p_S(cloud.x_m[i], cloud.y_m[i], cloud.z_m[i]);
    if (!p_S.allFinite() || p_S.squaredNorm() < min_range2) {
      ++st.too_close;
      continue;
    }
    const std::int64_t t_us = cloud.utime + cloud.time_offset_ns[i] / 1000;
    const Eigen::Vector3d p_B = R_B_S * p_S + t_B_S;
    if (self_) {
      const std::int64_t slot = (static_cast<std::int64_t>(cloud.time_offset_ns[i]) - off_min) / period_ns;
      if (slot != arm_slot) {
        arm_slot = slot;
        RobotConfiguration arm;
        states.at(cloud.utime + (off_min + (slot * period_ns + period_ns / 2)) / 1000, arm);
        self_->set_arm(arm.q_rad);
      }
      if (self_->contains(p_B)) {
        ++st.self;
        if (self_removed) (*self_removed)[i] = 1;
        continue;
      }
    }
    if (states.at(t_us, c) != StateBuffer::Lookup::inside) ++st.state_outside;
    const double cy = std::cos(c.base.yaw_rad), sy = std::sin(c.base.yaw_rad);
    out.points_W.emplace_back(static_cast<float>(cy * p_B.x() - sy * p_B.y() + c.base.x_m),
                              static_cast<float>(sy * p_B.x() + cy * p_B.y() + c.base.y_m),
                              static_cast<float>(p_B.z()));
  }
  RobotConfiguration mid;
  states.at(cloud.utime + (off_min + (off_max - off_min) / 2) / 1000, mid);
  out.origin_W = (mid.base.T_W_B() * params_.T_B_S).translation().cast<float>();
  states.at(out.utime_end, out.robot);
  if (params_.voxel_grid_leaf_m > 0.0) {
    const std::size_t before = out.points_W.size();
    voxel_grid_filter(out.points_W, params_.voxel_grid_leaf_m);
    st.voxel_grid_removed = before - out.points_W.size();
  }
  if (params_.outlier_mean_k > 0) {
    st.outliers = statistical_outlier_filter(out.points_W, params_.outlier_mean_k, params_.outlier_stddev_mul);
  }
  st.points_out = out.points_W.size();
  st.filter_s = seconds_since(t0);
  return st;
}

CloudReport Mapper::integrate(const FilteredCloud& cloud) {
  const auto t0 = std::chrono::steady_clock::now();
  CloudReport r;
  if (!centered_ || map_.needs_recenter(cloud.robot.base.x_m, cloud.robot.base.y_m, params_.recenter_distance_m)) {
    r.recentered = map_.center_on(cloud.robot.base.x_m, cloud.robot.base.y_m);
    centered_ = true;
  }
  IntegrateOptions opt;
  opt.max_range_m = params_.max_range_m;
  opt.ground_height_m = params_.ground_height_m;
  r.integrate = map_.integrate(cloud.origin_W, cloud.points_W, opt);
  last_.utime_end = cloud.utime_end;
  last_.origin_W = cloud.origin_W;
  last_.robot = cloud.robot;
  r.integrate_s = seconds_since(t0);
  return r;
}

CloudReport Mapper::process(const SensorCloud& cloud, const StateBuffer& states) {
  const FilterStats f = filter(cloud, states, scratch_);
  CloudReport r = integrate(scratch_);
  r.filter = f;
  return r;
}

}  // namespace porter::mapping
