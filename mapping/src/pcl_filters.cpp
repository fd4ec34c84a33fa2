#include "porter/mapping/pcl_filters.hpp"

#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace porter::mapping {

namespace {
pcl::PointCloud<pcl::PointXYZ>::Ptr to_pcl(const std::vector<Eigen::Vector3f>& points) {
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    (*cloud)[i].x = points[i].x();
    (*cloud)[i].y = points[i].y();
    (*cloud)[i].z = points[i].z();
  }
  return cloud;
}
void from_pcl(const pcl::PointCloud<pcl::PointXYZ>& cloud, std::vector<Eigen::Vector3f>& points) {
  points.resize(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) points[i] = Eigen::Vector3f(cloud[i].x, cloud[i].y, cloud[i].z);
}
}  // namespace

void voxel_grid_filter(std::vector<Eigen::Vector3f>& points, double leaf_m) {
  if (points.empty()) return;
  auto in = to_pcl(points);
  pcl::PointCloud<pcl::PointXYZ> out;
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setInputCloud(in);
  const float leaf = static_cast<float>(leaf_m);
  grid.setLeafSize(leaf, leaf, leaf);
  grid.filter(out);
  from_pcl(out, points);
}

std::size_t statistical_outlier_filter(std::vector<Eigen::Vector3f>& points, int mean_k, double stddev_mul) {
  if (points.size() <= static_cast<std::size_t>(mean_k)) return 0;
  auto in = to_pcl(points);
  pcl::PointCloud<pcl::PointXYZ> out;
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
  sor.setInputCloud(in);
  sor.setMeanK(mean_k);
  sor.setStddevMulThresh(stddev_mul);
  sor.filter(out);
  const std::size_t removed = points.size() - out.size();
  from_pcl(out, points);
  return removed;
}

}  // namespace porter::mapping
