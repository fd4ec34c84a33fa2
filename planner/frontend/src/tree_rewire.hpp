#pragma once
// RRT* rewiring shared by the layered arm search and the whole-body RRT*: move a node under a
// new parent and shift the cost of its whole subtree by the change. Node must have
// `int parent`, `std::vector<int> children` and `double cost`.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace porter::frontend {

template <class Node>
void reparent_subtree(std::vector<Node>& nodes, int child, int new_parent, double new_cost) {
  Node& c = nodes[static_cast<std::size_t>(child)];
  auto& siblings = nodes[static_cast<std::size_t>(c.parent)].children;
  siblings.erase(std::remove(siblings.begin(), siblings.end(), child), siblings.end());
  c.parent = new_parent;
  nodes[static_cast<std::size_t>(new_parent)].children.push_back(child);
  const double delta = new_cost - c.cost;
  std::vector<int> stack{child};
  while (!stack.empty()) {
    const int id = stack.back();
    stack.pop_back();
    nodes[static_cast<std::size_t>(id)].cost += delta;
    for (int k : nodes[static_cast<std::size_t>(id)].children) stack.push_back(k);
  }
}

}  // namespace porter::frontend
