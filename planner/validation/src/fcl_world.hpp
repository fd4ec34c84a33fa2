#pragma once
// FCL objects for the robot's bodies and the scene's obstacles, and the exact queries the
// validator makes on them. Private to porter_validation.
//
// Every shape is its own FCL object: boxes, cylinders and spheres as FCL primitives, meshes as
// OBBRSS BVH models. Signed distance: the FCL distance when separate; when FCL reports contact,
// minus the largest penetration depth of the contacts FCL returns (for primitive pairs the depth
// of the pair; for a mesh, the deepest of its triangles' contacts).
//
// Thread-safety: a world belongs to one thread (FCL objects carry their current transform).

#include <memory>
#include <string>
#include <vector>

#include <fcl/fcl.h>

#include "porter/core/geometry.hpp"
#include "porter/core/payload.hpp"
#include "porter/core/robot_model.hpp"
#include "porter/core/scene.hpp"
#include "porter/validation/chain_kinematics.hpp"

namespace porter::validation {

struct FclShape {
  int body = -1;                                   ///< owner body, or -1 for an obstacle
  std::string name;
  ShapeGeometry geometry;                          ///< for the exact lowest point (ground)
  Eigen::Isometry3d T_body_shape = Eigen::Isometry3d::Identity();
  std::unique_ptr<fcl::CollisionObjectd> object;
  fcl::AABBd aabb_W;                               ///< refreshed by place()
};

class FclWorld {
 public:
  FclWorld(const RobotModel& model, const Payload& payload, const Scene& scene);

  /// Moves every robot shape to its body's pose and refreshes the world AABBs.
  void place(const BodyPoses& T_W_body);

  std::vector<FclShape>& robot() { return robot_; }
  std::vector<FclShape>& obstacles() { return obstacles_; }

  /// Signed distance between two placed objects (negative: penetration depth).
  static double signed_distance(const FclShape& a, const FclShape& b);
  /// Penetration depth >= 0 when the objects are in contact, or a negative value when they are not.
  static double contact_depth(const FclShape& a, const FclShape& b);
  /// Lowest z of a placed robot shape in W (exact for primitives and mesh vertices).
  double lowest_z_W(const FclShape& s, const BodyPoses& T_W_body) const;

 private:
  std::vector<FclShape> robot_;
  std::vector<FclShape> obstacles_;
};

/// Lower bound of the distance between two boxes (0 when they overlap).
double aabb_gap(const fcl::AABBd& a, const fcl::AABBd& b);

}  // namespace porter::validation
