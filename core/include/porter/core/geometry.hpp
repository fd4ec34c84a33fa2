#pragma once
// Exact collision geometry: primitives and triangle meshes placed in a parent frame.
//
// Used for robot links (placed in the link frame), payloads (in the payload frame) and scene
// obstacles (in the world frame). The voxelizers, the reference collision checks and the SDF
// builders all read these shapes; nothing here approximates.
//
// Thread-safety: all types are values (meshes are shared immutable data); free functions are
// reentrant.

#include <memory>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace porter {

/// Axis-aligned box centred on its frame's origin.
struct Box {
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  ///< full edge lengths along x, y, z
};

/// Cylinder whose axis is its frame's z axis, centred on the origin.
struct Cylinder {
  double radius_m = 0.0;
  double length_m = 0.0;  ///< along z, from -length/2 to +length/2
};

struct Sphere {
  double radius_m = 0.0;
};

/// Indexed triangle mesh, vertices in metres in the mesh's own frame (scale already applied).
/// Triangles are counter-clockwise seen from outside when the mesh is closed; closedness is
/// reported by `closed` (every edge shared by exactly two triangles), which decides whether
/// point-inside queries are meaningful.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices_m;
  std::vector<Eigen::Vector3i> triangles;
  bool closed = false;
  std::string source;  ///< file it came from, for messages

  Eigen::AlignedBox3d bounds() const;
};

using MeshPtr = std::shared_ptr<const TriangleMesh>;

struct MeshShape {
  MeshPtr mesh;
};

using ShapeGeometry = std::variant<Box, Cylinder, Sphere, MeshShape>;

/// One piece of geometry and its pose in the parent frame (link, payload or world).
struct CollisionShape {
  ShapeGeometry geometry;
  Eigen::Isometry3d T_parent_shape = Eigen::Isometry3d::Identity();
  std::string name;  ///< for messages ("link3/collision[1]", "obstacle 'wall_left'")
};

/// Axis-aligned bounds of a shape after placing it with T_frame_parent * shape.T_parent_shape.
Eigen::AlignedBox3d shape_bounds(const CollisionShape& shape,
                                 const Eigen::Isometry3d& T_frame_parent = Eigen::Isometry3d::Identity());

/// Largest distance from `center_parent` to any point of the shape.
double shape_max_distance(const CollisionShape& shape, const Eigen::Vector3d& center_parent);

/// Signed distance (negative inside) from a point in the shape's parent frame to the shape.
/// Exact for primitives. For meshes: distance to the nearest triangle, negative inside when the
/// mesh is closed (inside decided by the generalized winding number); unsigned when open.
double shape_signed_distance(const CollisionShape& shape, const Eigen::Vector3d& p_parent);

/// True when the point (parent frame) is inside or on the shape.
bool shape_contains(const CollisionShape& shape, const Eigen::Vector3d& p_parent);

/// True when the shape intersects the axis-aligned box `box_parent` (parent frame). Exact
/// separating-axis tests for boxes and triangles, exact closest-point tests for spheres and
/// cylinders. Used by voxelizers: a voxel is occupied when it intersects the shape.
bool shape_intersects_aabb(const CollisionShape& shape, const Eigen::AlignedBox3d& box_parent);

/// Closest point on triangle (a, b, c) to p.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// Exact triangle / axis-aligned box overlap (Akenine-Möller separating axes).
bool triangle_intersects_aabb(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c, const Eigen::AlignedBox3d& box);

/// Ray cast against a shape: distance along the unit direction to the first hit in
/// [0, max_range_m], or a negative value when there is none.
double shape_ray_cast(const CollisionShape& shape, const Eigen::Vector3d& origin_parent,
                      const Eigen::Vector3d& unit_dir_parent, double max_range_m);

/// Triangulated copy of any shape (cylinders with `segments` facets), in the parent frame.
/// Used where a mesh is required (FCL validation, mesh export, pictures).
TriangleMesh shape_to_mesh(const CollisionShape& shape, int segments = 32);

}  // namespace porter
