#pragma once
// First-hit ray casting for the simulated LiDAR with Embree: the world's obstacles (and
// optionally the ground plane z = 0) in one static Embree scene, and each planning link of the
// robot, payload included, in its own scene in the link frame. The world scene is rebuilt by
// set_obstacles() (obstacles added or removed at run time); the robot's scenes are built once
// by set_robot() and posed by set_link_poses(), which costs nothing but eight transforms: a ray
// is tested against a link's bounding sphere in the world and, when it passes, cast in the link
// frame.
//
// Geometry: triangle meshes as given; boxes as 12 triangles; spheres exactly (Embree sphere
// points); cylinders as prisms whose faces lie within +-tessellation_tolerance_m of the true
// surface (vertices slightly outside, edge midpoints slightly inside). Rays see surfaces from
// both sides, so a ray leaving a solid it starts in hits the inside of its surface (the sensor
// is never inside an obstacle in a valid simulation; the sensor housing lies inside the minimum
// range). Embree computes in single precision: distances carry ~1e-6 relative error.
//
// Robot shapes whose name starts with "payload '" (the names attach_payload() gives) are
// reported as payload hits, the others as robot hits with their planning link.
//
// Failure: Embree device or scene errors are kept in error() and ok() turns false; a scene that
// is not ok hits nothing. Nothing throws at run time.
// Thread-safety: cast() is const and may run on many threads while no setter runs; setters
// need exclusive access.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "porter/core/geometry.hpp"
#include "porter/core/robot_model.hpp"

namespace porter::livox::sim {

enum class HitKind : std::uint8_t { none = 0, ground, obstacle, robot, payload };

/// "none", "ground", "obstacle", "robot", "payload".
const char* to_string(HitKind kind);

struct RayHit {
  float distance_m = -1.0f;  ///< along the unit direction; < 0 when nothing was hit
  HitKind kind = HitKind::none;
  /// obstacle: index into the obstacles given to set_obstacles(); robot / payload: planning
  /// link (0..7); -1 otherwise.
  int index = -1;
  float cos_incidence = 0.0f;  ///< |cos| of the angle between the ray and the surface normal
  bool hit() const { return kind != HitKind::none; }
};

struct RaySceneParams {
  bool ground_plane = true;               ///< add the plane z = 0 (the scene's ground)
  double ground_half_extent_m = 1000.0;   ///< the ground is a square of this half-size
  double tessellation_tolerance_m = 0.0005;  ///< cylinder prisms: max radial error (> 0)
};

class RayScene {
 public:
  explicit RayScene(const RaySceneParams& params = {});
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  /// Replaces the world's obstacles (world frame).
  void set_obstacles(const std::vector<CollisionShape>& obstacles_W);
  /// Builds one scene per planning link of `robot` (payload shapes included when attached).
  void set_robot(const RobotModel& robot);
  /// Poses of the planning link frames in the world (from forward_kinematics()).
  void set_link_poses(const std::array<Eigen::Isometry3d, kNumLinks>& T_W_L);

  /// Nearest hit along origin + t * unit_dir for t in [t_near, t_far].
  RayHit cast(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& unit_dir_W, float t_near,
              float t_far) const;
  /// The same, against the world only (no robot).
  RayHit cast_world(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& unit_dir_W,
                    float t_near, float t_far) const;

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  /// Triangles in the world scene (ground included) and in all link scenes.
  std::size_t world_triangles() const { return world_triangles_; }
  std::size_t robot_triangles() const { return robot_triangles_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  RaySceneParams params_;
  std::string error_;
  std::size_t world_triangles_ = 0;
  std::size_t robot_triangles_ = 0;
};

}  // namespace porter::livox::sim
