#pragma once
// The mapper's pipeline for one LiDAR scan, free of middleware:
//
//   filter():    range filter (sensor frame), self-filter (base frame, arm at each point's
//                time), de-skew (each point placed with the base pose interpolated to its own
//                time), optional PCL voxel grid and statistical outlier removal; gives the
//                world-frame points and the one sensor origin the scan is integrated from.
//   integrate(): recentres the bounded window on the robot when it moved far enough and
//                integrates the filtered points (rolling_map.hpp).
//   process():   both.
//
// The filtered cloud is exactly what stock octomap::OcTree::insertPointCloud(points, origin,
// max_range_m) would be given for the same update, which is how the tests and the benchmark
// compare the two.
//
// Time: µs, the clock of the clouds and of the state buffer. Frames: S (the sensor's point
// frame), B (base), W (world). Thread-safety: one thread per Mapper.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/robot_model.hpp"
#include "porter/mapping/rolling_map.hpp"
#include "porter/mapping/self_filter.hpp"
#include "porter/mapping/state_buffer.hpp"

namespace porter::mapping {

/// One scan as the LiDAR driver sends it (point_cloud_t without the middleware).
struct SensorCloud {
  std::int64_t utime = 0;                  ///< time of the scan's first point, µs
  std::vector<float> x_m, y_m, z_m;        ///< points in the sensor frame S, m
  std::vector<std::int32_t> time_offset_ns;  ///< point i at utime + offset / 1000 µs
  std::size_t size() const { return x_m.size(); }
};

struct MapperParams {
  RollingMapParams map;
  /// The window recentres when the robot is farther than this from its centre (x or y), m.
  double recenter_distance_m = 2.0;
  Eigen::Isometry3d T_B_S = Eigen::Isometry3d::Identity();  ///< sensor in the base frame
  double min_range_m = 0.1;        ///< closer points are dropped (sensor housing, blind zone)
  double max_range_m = 12.0;       ///< farther points only clear space up to this range
  double ground_height_m = 0.05;   ///< points with world z below this are ground (no hit)
  bool self_filter = true;
  SelfFilterParams self;
  /// The arm is posed for the self-filter on this time grid within a scan, s (> 0).
  double arm_pose_period_s = 0.005;
  double voxel_grid_leaf_m = 0.0;  ///< PCL VoxelGrid leaf, m; 0 = off
  int outlier_mean_k = 0;          ///< PCL StatisticalOutlierRemoval neighbours; 0 = off
  double outlier_stddev_mul = 1.0; ///< its standard-deviation multiplier
};

/// Checks ranges; returns "" when valid, else what is wrong (for the config loader).
std::string validate(const MapperParams& p);

/// A scan ready to integrate.
struct FilteredCloud {
  std::int64_t utime_end = 0;            ///< time of the scan's last point, µs
  Eigen::Vector3f origin_W = Eigen::Vector3f::Zero();  ///< sensor at the scan's middle time
  RobotConfiguration robot;              ///< configuration at utime_end
  std::vector<Eigen::Vector3f> points_W;
};

struct FilterStats {
  std::uint64_t points_in = 0;
  std::uint64_t too_close = 0;      ///< below min_range_m (or not finite)
  std::uint64_t self = 0;           ///< removed by the self-filter
  std::uint64_t voxel_grid_removed = 0;
  std::uint64_t outliers = 0;
  std::uint64_t points_out = 0;
  std::uint64_t state_outside = 0;  ///< point times outside the state buffer (nearest state held)
  double filter_s = 0.0;            ///< wall time of filter(), s
};

struct CloudReport {
  FilterStats filter;
  IntegrateStats integrate;
  bool recentered = false;
  double integrate_s = 0.0;
};

class Mapper {
 public:
  /// `robot` with its payload attached (the self-filter uses all of link 7's shapes).
  Mapper(const RobotModel& robot, const MapperParams& params);
  ~Mapper();

  /// Filters one scan (see above) into `out`. `self_removed`, when given, receives one flag per
  /// input point: 1 when the self-filter removed it (for tests and diagnostics).
  FilterStats filter(const SensorCloud& cloud, const StateBuffer& states, FilteredCloud& out,
                     std::vector<std::uint8_t>* self_removed = nullptr);
  /// Integrates a filtered scan.
  CloudReport integrate(const FilteredCloud& cloud);
  /// filter() then integrate().
  CloudReport process(const SensorCloud& cloud, const StateBuffer& states);

  /// Replaces the robot model (a payload grasped or released).
  void set_robot(const RobotModel& robot);

  const RollingMap& map() const { return map_; }
  RollingMap& map() { return map_; }
  const MapperParams& params() const { return params_; }
  const SelfFilter* self_filter() const { return self_.get(); }
  /// The last scan given to integrate() (its time and the robot's configuration then).
  const FilteredCloud& last() const { return last_; }

 private:
  MapperParams params_;
  RollingMap map_;
  std::unique_ptr<SelfFilter> self_;
  FilteredCloud scratch_;
  FilteredCloud last_;
  bool centered_ = false;
};

}  // namespace porter::mapping
