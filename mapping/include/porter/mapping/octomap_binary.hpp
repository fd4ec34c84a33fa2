#pragma once
// The rolling map as an OctoMap binary stream, written straight from the dense window without
// building an octomap::OcTree: the bytes equal what octomap::OcTree::writeBinaryData writes for
// a tree (depth 16, the map's resolution) whose leaves are exactly the window's known voxels,
// each at log-odds of its state (after the tree's toMaxLikelihood() and prune(): a node whose
// eight children are all known leaves of one state is written as one leaf). An empty map gives
// an empty stream (no root). Read it with octomap::OcTree(res).readBinaryData(stream).
//
// Thread-safety: reads the map only.

#include <cstdint>
#include <vector>

#include "porter/mapping/rolling_map.hpp"

namespace porter::mapping {

/// Replaces `out` with the stream.
void write_octomap_binary(const RollingMap& map, std::vector<std::uint8_t>& out);

}  // namespace porter::mapping
