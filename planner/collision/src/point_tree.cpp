#include "porter/planner/collision/point_tree.hpp"

#include <algorithm>
#include <cmath>

namespace porter::planner {

int PointTreePool::add_tree(const std::vector<Eigen::Vector3f>& points, int leaf_size) {
  std::vector<Eigen::Vector3f> pts = points;
  if (!pts.empty()) build(pts, 0, static_cast<std::uint32_t>(pts.size()), std::max(1, leaf_size));
  tree_begin_.push_back(static_cast<std::uint32_t>(nodes_.size()));
  point_begin_.push_back(static_cast<std::uint32_t>(x_.size()));
  return num_trees() - 1;
}

std::size_t PointTreePool::tree_size(int tree) const {
  const auto t = static_cast<std::size_t>(tree);
  return point_begin_[t + 1] - point_begin_[t];
}

std::uint32_t PointTreePool::build(std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end,
                                   int leaf_size) {
  Eigen::Vector3f c;
  const float radius = points_sphere(pts, begin, end, &c);
  const auto index = static_cast<std::uint32_t>(nodes_.size());
  PointTreeNode node;
  node.cx = c.x();
  node.cy = c.y();
  node.cz = c.z();
  node.radius_m = radius;
  nodes_.push_back(node);
  const std::uint32_t count = end - begin;
  if (count <= static_cast<std::uint32_t>(leaf_size)) {
    nodes_[index].first_point = static_cast<std::uint32_t>(x_.size());
    nodes_[index].num_points = count;
    for (std::uint32_t k = begin; k < end; ++k) {
      x_.push_back(pts[k].x());
      y_.push_back(pts[k].y());
      z_.push_back(pts[k].z());
    }
  } else {
    int axis = 0;
    points_box(pts, begin, end).sizes().maxCoeff(&axis);
    const std::uint32_t mid = begin + count / 2;
    std::nth_element(pts.begin() + begin, pts.begin() + mid, pts.begin() + end,
                     [axis](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return a[axis] < b[axis]; });
    build(pts, begin, mid, leaf_size);
    build(pts, mid, end, leaf_size);
  }
  nodes_[index].skip = static_cast<std::uint32_t>(nodes_.size());
  return index;
}

std::size_t PointTreePool::bytes() const {
  return nodes_.size() * sizeof(PointTreeNode) + 3 * x_.size() * sizeof(float) +
         (tree_begin_.size() + point_begin_.size()) * sizeof(std::uint32_t);
}

std::vector<Eigen::Vector3f> PointTreePool::points(int tree) const {
  std::vector<Eigen::Vector3f> out;
  for (std::uint32_t i = tree_begin(tree); i < tree_end(tree); ++i) {
    const PointTreeNode& n = nodes_[i];
    for (std::uint32_t k = n.first_point; k < n.first_point + n.num_points; ++k) out.emplace_back(x_[k], y_[k], z_[k]);
  }
  return out;
}

}  // namespace porter::planner
