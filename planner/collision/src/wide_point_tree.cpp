#include "porter/planner/collision/wide_point_tree.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace porter::planner {

namespace {

struct Sphere {
  Eigen::Vector3f centre;
  float radius;
};

Sphere bounding_sphere(const std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end) {
  Eigen::Vector3f lo = pts[begin], hi = pts[begin];
  for (std::uint32_t k = begin + 1; k < end; ++k) {
    lo = lo.cwiseMin(pts[k]);
    hi = hi.cwiseMax(pts[k]);
  }
  const Eigen::Vector3f c = 0.5f * (lo + hi);
  float r2 = 0.f;
  for (std::uint32_t k = begin; k < end; ++k) r2 = std::max(r2, (pts[k] - c).squaredNorm());
  return {c, std::sqrt(r2) * (1.f + 1e-6f) + 1e-7f};
}

/// Splits [begin, end) into at most `parts` groups at medians of the longest axis, every split
/// after a multiple of eight points (the remainder ends in the last group).
void split(std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end, int parts,
           std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) {
  const std::uint32_t blocks = (end - begin + 7) / 8;
  if (parts <= 1 || blocks <= 1) {
    out.emplace_back(begin, end);
    return;
  }
  Eigen::Vector3f lo = pts[begin], hi = pts[begin];
  for (std::uint32_t k = begin + 1; k < end; ++k) {
    lo = lo.cwiseMin(pts[k]);
    hi = hi.cwiseMax(pts[k]);
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::uint32_t mid = begin + 8 * (blocks / 2);
  std::nth_element(pts.begin() + begin, pts.begin() + mid, pts.begin() + end,
                   [axis](const Eigen::Vector3f& a, const Eigen::Vector3f& b) { return a[axis] < b[axis]; });
  split(pts, begin, mid, parts / 2, out);
  split(pts, mid, end, parts - parts / 2, out);
}

}  // namespace

int WidePointTreePool::add_tree(const std::vector<Eigen::Vector3f>& points) {
  WideTreeRoot root;
  root.num_points = static_cast<std::uint32_t>(points.size());
  if (!points.empty()) {
    std::vector<Eigen::Vector3f> pts = points;
    const Sphere s = bounding_sphere(pts, 0, root.num_points);
    root.cx = s.centre.x();
    root.cy = s.centre.y();
    root.cz = s.centre.z();
    root.radius_m = s.radius;
    root.ref = build(pts, 0, root.num_points, 0);
  }
  roots_.push_back(root);
  block_begin_.push_back(static_cast<std::uint32_t>(blocks_.size()));
  return num_trees() - 1;
}

std::int32_t WidePointTreePool::build(std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end,
                                      int depth) {
  if (depth > kMaxDepth) throw std::length_error("WidePointTreePool: tree deeper than kMaxDepth");
  const std::uint32_t count = end - begin;
  if (count <= 8) {
    PointBlock b;
    for (std::uint32_t i = 0; i < 8; ++i) {
      const Eigen::Vector3f& p = pts[begin + std::min(i, count - 1)];
      b.x[i] = p.x();
      b.y[i] = p.y();
      b.z[i] = p.z();
    }
    blocks_.push_back(b);
    block_count_.push_back(static_cast<std::uint8_t>(count));
    return ~static_cast<std::int32_t>(blocks_.size() - 1);
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> groups;
  split(pts, begin, end, 8, groups);
  const auto index = static_cast<std::int32_t>(nodes_.size());
  nodes_.emplace_back();
  WideNode node;  // filled here, stored after the children (nodes_ may reallocate)
  for (int i = 0; i < 8; ++i) {
    node.cx[i] = node.cy[i] = node.cz[i] = node.r[i] = 0.f;
    node.child[i] = 0;
  }
  for (std::size_t i = 0; i < groups.size(); ++i) {
    const Sphere s = bounding_sphere(pts, groups[i].first, groups[i].second);
    node.cx[i] = s.centre.x();
    node.cy[i] = s.centre.y();
    node.cz[i] = s.centre.z();
    node.r[i] = s.radius;
    node.child[i] = build(pts, groups[i].first, groups[i].second, depth + 1);
    node.used |= 1u << i;
  }
  nodes_[static_cast<std::size_t>(index)] = node;
  return index;
}

std::size_t WidePointTreePool::bytes() const {
  return nodes_.size() * sizeof(WideNode) + blocks_.size() * sizeof(PointBlock) + block_count_.size() +
         roots_.size() * sizeof(WideTreeRoot) + block_begin_.size() * sizeof(std::uint32_t);
}

std::vector<Eigen::Vector3f> WidePointTreePool::points(int tree) const {
  std::vector<Eigen::Vector3f> out;
  const auto t = static_cast<std::size_t>(tree);
  for (std::uint32_t b = block_begin_[t]; b < block_begin_[t + 1]; ++b)
    for (std::uint32_t i = 0; i < block_count_[b]; ++i) out.emplace_back(blocks_[b].x[i], blocks_[b].y[i], blocks_[b].z[i]);
  return out;
}

}  // namespace porter::planner
