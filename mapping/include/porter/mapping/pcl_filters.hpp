#pragma once
// PCL filters on world-frame points, in their own translation unit so PCL's headers stay out
// of the rest of the mapper: VoxelGrid downsampling (one point per leaf, the centroid) and
// StatisticalOutlierRemoval (a point whose mean distance to its k nearest neighbours exceeds
// the cloud's mean by stddev_mul standard deviations is dropped).
//
// Thread-safety: reentrant.

#include <vector>

#include <Eigen/Core>

namespace porter::mapping {

/// Replaces `points` with one centroid per occupied leaf of edge leaf_m (> 0).
void voxel_grid_filter(std::vector<Eigen::Vector3f>& points, double leaf_m);
/// Removes statistical outliers (mean_k >= 1); returns how many were removed.
std::size_t statistical_outlier_filter(std::vector<Eigen::Vector3f>& points, int mean_k, double stddev_mul);

}  // namespace porter::mapping
