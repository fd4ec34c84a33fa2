#pragma once
// Exact signed distances of a set of shapes at every node of an SdfGrid (internal to
// porter_backend; used by LinkSdf::build and tested through it).

#include <vector>

#include "porter/backend/sdf_grid.hpp"
#include "porter/core/geometry.hpp"

namespace porter::backend::detail {

/// Writes min over shapes of the exact signed distance (negative inside) at every node. Shapes are
/// placed in the grid's frame by their T_parent_shape. Primitives use shape_signed_distance; a
/// mesh uses the nearest-triangle distance signed by shape_contains (generalized winding number,
/// closed meshes; open meshes are unsigned, as shape_signed_distance does). Node values are exact;
/// the work is pruned by octree subdivision: in a node box of centre c and half-diagonal rho, an
/// element (primitive or triangle, each a 1-Lipschitz distance) can be the minimizer at some node
/// only if its distance at c is within 2 rho of the smallest one, and a mesh's sign is constant in
/// the box once its unsigned distance at c exceeds rho.
void fill_exact_sdf(const std::vector<CollisionShape>& shapes, SdfGrid& grid);

}  // namespace porter::backend::detail
