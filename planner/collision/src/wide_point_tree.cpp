#include "porter/planner/collision/wide_point_tree.hpp"

#include <algorithm>
#include <limits>
#include <tuple>
#include <stdexcept>

#include "porter/planner/collision/point_tree.hpp"

namespace porter::planner {

namespace {

/// Splits [begin, end) into at most `parts` groups, in two halves at a time: each cut after a
/// whole number of blocks (eight points; the remainder ends in the last group), between a quarter
/// and three quarters of the blocks, along the axis and at the place where the two halves' boxes
/// have the smallest sum of diagonals.
void split(std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end, int parts,
           std::vector<std::pair<std::uint32_t, std::uint32_t>>& out) {
  const std::uint32_t n = end - begin, blocks = (n + 7) / 8;
  if (parts <= 1 || blocks <= 1) {
    out.emplace_back(begin, end);
    return;
  }
  // A total order per axis (ties broken by the other coordinates), so sorting again along the
  // chosen axis reproduces the order its cuts were scored in.
  auto by_axis = [](int a) {
    return [a](const Eigen::Vector3f& p, const Eigen::Vector3f& q) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      return std::tie(p[a], p[b], p[c]) < std::tie(q[a], q[b], q[c]);
    };
  };
  std::uint32_t lo = std::max<std::uint32_t>(1, blocks / 4), hi = blocks - lo;
  if (blocks <= static_cast<std::uint32_t>(parts)) {  // then each half must fit its parts: one block per group
    lo = std::max(lo, blocks - static_cast<std::uint32_t>(parts - parts / 2));
    hi = std::min(hi, static_cast<std::uint32_t>(parts / 2));
  }
  int axis = 0;
  std::uint32_t cut = blocks / 2;
  float best = std::numeric_limits<float>::infinity();
  std::vector<float> prefix(n + 1), suffix(n + 1);  // box diagonals of the first i / from i on
  for (int a = 0; a < 3; ++a) {
    std::sort(pts.begin() + begin, pts.begin() + end, by_axis(a));
    Eigen::AlignedBox3f box;
    box.setEmpty();
    for (std::uint32_t i = 0; i < n; ++i) prefix[i + 1] = box.extend(pts[begin + i]).diagonal().norm();
    box.setEmpty();
    for (std::uint32_t i = n; i > 0; --i) suffix[i - 1] = box.extend(pts[begin + i - 1]).diagonal().norm();
    for (std::uint32_t k = lo; k <= hi && 8 * k < n; ++k) {
      const float cost = prefix[8 * k] + suffix[8 * k];
      if (cost < best) {
        best = cost;
        axis = a;
        cut = k;
      }
    }
  }
  if (axis != 2) std::sort(pts.begin() + begin, pts.begin() + end, by_axis(axis));  // 2: sorted last
  const std::uint32_t mid = begin + 8 * cut;
  split(pts, begin, mid, parts / 2, out);
  split(pts, mid, end, parts - parts / 2, out);
}

}  // namespace

int WidePointTreePool::add_tree(const std::vector<Eigen::Vector3f>& points) {
  WideTreeRoot root;
  root.num_points = static_cast<std::uint32_t>(points.size());
  if (!points.empty()) {
    std::vector<Eigen::Vector3f> pts = points;
    Eigen::Vector3f c;
    root.radius_m = points_sphere(pts, 0, root.num_points, &c);
    root.cx = c.x();
    root.cy = c.y();
    root.cz = c.z();
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
    Eigen::Vector3f c;
    node.r[i] = points_sphere(pts, groups[i].first, groups[i].second, &c);
    node.cx[i] = c.x();
    node.cy[i] = c.y();
    node.cz[i] = c.z();
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
