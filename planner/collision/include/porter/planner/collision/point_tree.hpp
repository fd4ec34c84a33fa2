#pragma once
// Sphere trees over point sets, many trees in one pool (one tree per kernel sample).
//
// A tree bounds a set of points (in the frame the points were given in) by nested spheres:
// each node's sphere contains every point of its subtree; leaves hold at most `leaf_size`
// points. Nodes are stored in depth-first pre-order with a skip index (the node after the
// subtree), so a query walks them without a stack: test a node, and either descend (next node)
// or jump past its subtree (skip). Points are stored as float32 in structure-of-arrays form.
//
// Used by the back-end's self-collision penalty (surface samples of a link, a subtree skipped
// when the other link's SDF proves it beyond the penalty's reach). The kernel checks use the
// eight-wide trees of wide_point_tree.hpp instead.
//
// Thread-safety: immutable after construction; concurrent reads are safe.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace porter::planner {

struct PointTreeNode {
  float cx = 0.f, cy = 0.f, cz = 0.f;  ///< sphere centre, metres, frame of the points
  float radius_m = 0.f;                ///< every point of the subtree lies within this radius
  std::uint32_t skip = 0;              ///< pool index of the first node after this subtree
  std::uint32_t first_point = 0;       ///< leaves: pool index of the first point
  std::uint32_t num_points = 0;        ///< > 0 for a leaf, 0 for an internal node
};

/// Axis-aligned box of pts[begin, end) (begin < end).
inline Eigen::AlignedBox3f points_box(const std::vector<Eigen::Vector3f>& pts, std::uint32_t begin,
                                      std::uint32_t end) {
  Eigen::AlignedBox3f box(pts[begin]);
  for (std::uint32_t k = begin + 1; k < end; ++k) box.extend(pts[k]);
  return box;
}

/// Sphere around pts[begin, end): the box centre and the largest distance to a point, rounded
/// up by a relative 1e-6 so float rounding never shrinks it. Returns the radius.
inline float points_sphere(const std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end,
                           Eigen::Vector3f* centre) {
  *centre = points_box(pts, begin, end).center();
  float r2 = 0.f;
  for (std::uint32_t k = begin; k < end; ++k) r2 = std::max(r2, (pts[k] - *centre).squaredNorm());
  return std::sqrt(r2) * (1.f + 1e-6f) + 1e-7f;
}

class PointTreePool {
 public:
  /// Adds a tree over `points` (metres, any order; may be empty) and returns its index.
  /// leaf_size >= 1.
  int add_tree(const std::vector<Eigen::Vector3f>& points, int leaf_size);

  int num_trees() const { return static_cast<int>(tree_begin_.size()) - 1; }
  /// Node range [begin, end) of a tree in nodes(); empty for an empty tree.
  std::uint32_t tree_begin(int tree) const { return tree_begin_[static_cast<std::size_t>(tree)]; }
  std::uint32_t tree_end(int tree) const { return tree_begin_[static_cast<std::size_t>(tree) + 1]; }
  /// Number of points of a tree.
  std::size_t tree_size(int tree) const;

  const PointTreeNode* nodes() const { return nodes_.data(); }
  const float* x() const { return x_.data(); }
  const float* y() const { return y_.data(); }
  const float* z() const { return z_.data(); }
  std::size_t num_points() const { return x_.size(); }
  std::size_t num_nodes() const { return nodes_.size(); }
  std::size_t bytes() const;

  /// All points of a tree (for tests and pictures).
  std::vector<Eigen::Vector3f> points(int tree) const;

 private:
  std::uint32_t build(std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end, int leaf_size);

  std::vector<PointTreeNode> nodes_;
  std::vector<float> x_, y_, z_;
  std::vector<std::uint32_t> tree_begin_{0};
  std::vector<std::uint32_t> point_begin_{0};
};

/// Walks a tree: `node_free(node)` returns true when the node's whole sphere is known to be
/// free (the subtree is skipped); for the points of every leaf that is not skipped,
/// `point_hit(x, y, z)` returns true on a hit, which ends the walk. Returns true on a hit.
/// `skip_root_test`: the caller has already found the root not free (saves one test).
template <class NodeFree, class PointHit>
inline bool point_tree_any(const PointTreePool& pool, int tree, NodeFree&& node_free, PointHit&& point_hit,
                           bool skip_root_test = false) {
  const PointTreeNode* nodes = pool.nodes();
  const float* px = pool.x();
  const float* py = pool.y();
  const float* pz = pool.z();
  std::uint32_t i = pool.tree_begin(tree);
  const std::uint32_t end = pool.tree_end(tree);
  if (skip_root_test && i < end && nodes[i].num_points == 0) ++i;
  while (i < end) {
    const PointTreeNode& n = nodes[i];
    if (node_free(n)) {
      i = n.skip;
      continue;
    }
    if (n.num_points > 0) {
      const std::uint32_t e = n.first_point + n.num_points;
      for (std::uint32_t k = n.first_point; k < e; ++k)
        if (point_hit(px[k], py[k], pz[k])) return true;
      i = n.skip;
    } else {
      ++i;
    }
  }
  return false;
}

}  // namespace porter::planner
