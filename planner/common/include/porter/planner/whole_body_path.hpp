#pragma once
// The front-end's output and the mid-end's input: a discrete whole-body path split into
// segments of constant driving direction.

#include <vector>

#include "porter/core/types.hpp"

namespace porter::planner {

struct PathNode {
  RobotConfiguration config;
  double time_s = 0.0;  ///< allocated arrival time from the path start (initial guess for MINCO)
};

/// Nodes driven in one direction. eta = +1 forward, -1 reverse. Consecutive segments share
/// their gear-switch node: segments[i].nodes.back() and segments[i+1].nodes.front() are the
/// same configuration at the same time.
struct PathSegment {
  int eta = 1;
  std::vector<PathNode> nodes;
};

struct WholeBodyPath {
  std::vector<PathSegment> segments;

  bool empty() const { return segments.empty(); }
  std::size_t node_count() const {
    std::size_t n = 0;
    for (const auto& s : segments) n += s.nodes.size();
    return n;
  }
};

}  // namespace porter::planner
