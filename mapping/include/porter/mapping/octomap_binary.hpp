#pragma once
// The rolling map as an OctoMap binary stream, written straight from the dense window without
// building an octomap::OcTree: the bytes equal what octomap::OcTree::writeBinaryData writes for
// a tree (depth 16, the map's resolution) whose leaves are exactly the window's known voxels,
// each at log-odds of its state (after the tree's toMaxLikelihood() and prune(): a node whose
// eight children are all known leaves of one state is written as one leaf). An empty map gives
// an empty stream (no root). Read it with octomap::OcTree(res).readBinaryData(stream).
//
// Two writers of the same bytes:
// - write_octomap_binary(): reads every voxel of the window for every stream (~10 M voxels at
//   the shipped size); kept as the reference the incremental writer is checked against.
// - OctomapBinaryWriter: the format is a depth-first (pre-order) walk, so the bytes of the
//   subtree of a brick (an 8 x 8 x 8-voxel node, tree depth 13) depend on that brick's voxels
//   only. The writer keeps each brick's state and subtree bytes and re-encodes a brick only
//   when the map stamped one of its slot blocks since the last write (rolling_map.hpp) or the
//   window's edge moved across it; the levels above the bricks are walked anew and the cached
//   runs spliced in.
//
// Thread-safety: both read the map only; a writer is used by one thread at a time.

#include <cstdint>
#include <vector>

#include "porter/mapping/rolling_map.hpp"

namespace porter::mapping {

/// Replaces `out` with the stream (full encode).
void write_octomap_binary(const RollingMap& map, std::vector<std::uint8_t>& out);

/// Incremental writer (see above). One writer follows one map object: given another map (or
/// the same map after its dims or resolution changed) it starts over with a full encode.
class OctomapBinaryWriter {
 public:
  struct Stats {
    std::int64_t bricks = 0;          ///< bricks that meet the window
    std::int64_t bricks_encoded = 0;  ///< of those, re-encoded by this write
  };

  /// Replaces `out` with the stream of `map`, byte for byte what write_octomap_binary gives.
  void write(const RollingMap& map, std::vector<std::uint8_t>& out);
  /// Forgets the cache: the next write re-encodes every brick.
  void reset() { map_ = nullptr; }
  const Stats& last_stats() const { return stats_; }

 private:
  struct Brick {
    Eigen::Vector3i key{-1, -1, -1};  ///< brick coordinates (voxel key >> 3) the entry holds
    std::uint8_t code = 0;            ///< unknown / free / occupied leaf, or inner
    std::vector<std::uint8_t> bytes;  ///< pre-order bytes of the subtree when inner
  };
  Brick& entry(int bx, int by, int bz);
  void encode_brick(const RollingMap& map, int bx, int by, int bz, Brick& e);
  int node(int depth, int kx, int ky, int kz, std::vector<std::uint8_t>& out);

  const RollingMap* map_ = nullptr;
  Eigen::Vector3i dims_{0, 0, 0};
  double resolution_m_ = 0.0;
  std::uint64_t revision_ = 0;
  Eigen::Vector3i lo_, hi_;            ///< window keys at the last write
  Eigen::Vector3i ring_{0, 0, 0};      ///< brick cache size per axis (bricks indexed modulo it)
  std::vector<Brick> bricks_;
  std::vector<std::uint8_t> scratch_;
  Stats stats_;
};

}  // namespace porter::mapping
