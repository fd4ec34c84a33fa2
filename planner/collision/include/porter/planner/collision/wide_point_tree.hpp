#pragma once
// Eight-wide sphere trees over point sets, many trees in one pool: the layout the kernel queries
// walk eight spheres or eight points at a time (simd8.hpp).
//
// A tree bounds a set of points (in the frame they were given in) by nested spheres. Every node
// holds up to eight children in structure-of-arrays form: the sphere (centre, radius) containing
// the child's points, and a reference to the child, either another node or a block of at most
// eight points (also structure-of-arrays). A block with fewer than eight points repeats its last
// point in the spare lanes: a repeated point changes no "does any point hit" answer. Each tree
// also keeps its root sphere, so a query can try to dismiss the whole tree with one scalar test.
//
// Build: a node's points are cut in two, and each half again, until there are eight groups (or
// a group is one block); every cut falls after a whole number of blocks of eight points, so every
// block except at most one per node is full, and a set of at most 64 points is one node over
// blocks. A cut is placed between a quarter and three quarters of the blocks (and, once a node's
// blocks fit its eight groups, so that each half's blocks fit its groups), along the axis and
// at the place where the two halves' boxes have the smallest sum of diagonals. Why not the median
// of the longest axis: equal halves of a T-shaped payload mix stem and crossbar into two large
// first-level spheres; the cost rule leaves one large sphere (the T's junction) and seven small
// ones, so a walk near obstacles opens fewer nodes. The fit rule for small nodes keeps trees a
// level shallower. The price is build time (three sorts per cut), paid once per robot.
// Sphere centres are box centres, radii the largest distance to a point, rounded up by a
// relative 1e-6 so float rounding never shrinks a sphere.
//
// Why not the binary PointTreePool (point_tree.hpp): a binary walk tests one sphere per branch
// (one mispredicted branch and one table lookup each); here one node test costs about as many
// instructions for eight spheres, and the blocks test eight points per step.
//
// Thread-safety: immutable after construction; concurrent reads are safe.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "porter/planner/collision/simd8.hpp"

namespace porter::planner {

struct alignas(32) WideNode {
  float cx[8], cy[8], cz[8];  ///< child sphere centres (metres, frame of the points)
  float r[8];                 ///< child sphere radii; unused slots 0
  std::int32_t child[8];      ///< >= 0: node index; < 0: block index ~child
  std::uint32_t used = 0;     ///< bit i: slot i holds a child
};

struct alignas(32) PointBlock {
  float x[8], y[8], z[8];  ///< spare lanes repeat the last point
};

struct WideTreeRoot {
  float cx = 0.f, cy = 0.f, cz = 0.f, radius_m = 0.f;  ///< sphere around every point of the tree
  std::int32_t ref = 0;                                ///< root node (>= 0) or block (~index)
  std::uint32_t num_points = 0;                        ///< 0: empty tree (ref unused)
};

class WidePointTreePool {
 public:
  /// The deepest tree a query's stack allows (8^15 blocks: never reached in practice);
  /// add_tree throws std::length_error beyond it.
  static constexpr int kMaxDepth = 15;

  /// Adds a tree over `points` (metres, any order; may be empty) and returns its index.
  int add_tree(const std::vector<Eigen::Vector3f>& points);

  int num_trees() const { return static_cast<int>(roots_.size()); }
  const WideTreeRoot& root(int tree) const { return roots_[static_cast<std::size_t>(tree)]; }
  std::size_t tree_size(int tree) const { return root(tree).num_points; }
  const WideNode* nodes() const { return nodes_.data(); }
  const PointBlock* blocks() const { return blocks_.data(); }
  std::size_t num_nodes() const { return nodes_.size(); }
  std::size_t num_blocks() const { return blocks_.size(); }
  std::size_t bytes() const;

  /// All points of a tree, each once (for tests and pictures).
  std::vector<Eigen::Vector3f> points(int tree) const;

 private:
  std::int32_t build(std::vector<Eigen::Vector3f>& pts, std::uint32_t begin, std::uint32_t end, int depth);

  std::vector<WideNode> nodes_;
  std::vector<PointBlock> blocks_;
  std::vector<std::uint8_t> block_count_;  ///< points held by each block (1..8)
  std::vector<WideTreeRoot> roots_;
  std::vector<std::uint32_t> block_begin_{0};  ///< tree t's blocks: [block_begin_[t], block_begin_[t + 1])
};

/// Walks a tree: `open(node)` returns the bit mask of the node's slots whose spheres are NOT
/// known to be free (those subtrees are visited; others skipped); `block_hit(block)` returns true
/// when one of its points hits, which ends the walk. The caller tests the root sphere itself.
/// Returns true on a hit.
/// Forced inline, with the callbacks (declare them PORTER_SIMD_LAMBDA), so a multi-versioned caller
/// (PORTER_KERNEL_CLONES) runs the walk in its own instruction set.
template <class Open, class BlockHit>
PORTER_SIMD_INLINE bool wide_tree_any(const WidePointTreePool& pool, int tree, Open&& open, BlockHit&& block_hit) {
  const WideTreeRoot& root = pool.root(tree);
  if (root.num_points == 0) return false;
  if (root.ref < 0) return block_hit(pool.blocks()[~root.ref]);
  const WideNode* nodes = pool.nodes();
  const PointBlock* blocks = pool.blocks();
  std::int32_t stack[8 * WidePointTreePool::kMaxDepth];
  int top = 0;
  stack[top++] = root.ref;
  while (top > 0) {
    const WideNode& n = nodes[stack[--top]];
    std::uint32_t m = open(n) & n.used;
    while (m != 0) {
      const int i = __builtin_ctz(m);
      m &= m - 1;
      const std::int32_t c = n.child[i];
      if (c < 0) {
        if (block_hit(blocks[~c])) return true;
      } else {
        stack[top++] = c;
      }
    }
  }
  return false;
}

}  // namespace porter::planner
