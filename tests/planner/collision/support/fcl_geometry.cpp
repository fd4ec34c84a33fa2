#include "fcl_geometry.hpp"

#include <octomap/octomap.h>

#include <type_traits>
#include <variant>

#include "porter/core/kinematics.hpp"
#include "reference_collision.hpp"

namespace porter::test {

std::shared_ptr<fcl::CollisionGeometryd> mesh_to_fcl(const TriangleMesh& mesh) {
  auto bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Vector3d> v(mesh.vertices_m.begin(), mesh.vertices_m.end());
  std::vector<fcl::Triangle> t;
  for (const auto& tri : mesh.triangles)
    t.emplace_back(static_cast<std::size_t>(tri[0]), static_cast<std::size_t>(tri[1]),
                   static_cast<std::size_t>(tri[2]));
  bvh->beginModel();
  bvh->addSubModel(v, t);
  bvh->endModel();
  return bvh;
}

std::shared_ptr<fcl::CollisionGeometryd> shape_to_fcl(const CollisionShape& shape) {
  return std::visit(
      [](const auto& g) -> std::shared_ptr<fcl::CollisionGeometryd> {
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, Box>) {
          return std::make_shared<fcl::Boxd>(g.size_m.x(), g.size_m.y(), g.size_m.z());
        } else if constexpr (std::is_same_v<G, Cylinder>) {
          return std::make_shared<fcl::Cylinderd>(g.radius_m, g.length_m);
        } else if constexpr (std::is_same_v<G, Sphere>) {
          return std::make_shared<fcl::Sphered>(g.radius_m);
        } else {
          return mesh_to_fcl(*g.mesh);
        }
      },
      shape.geometry);
}

FclWorld::FclWorld(const RobotModel& model, const std::vector<CollisionShape>& obstacles_W) : model_(model) {
  for (const auto& o : obstacles_W) {
    CollisionShape local = o;
    local.T_parent_shape.setIdentity();
    obstacles_.push_back(std::make_unique<fcl::CollisionObjectd>(mesh_to_fcl(shape_to_mesh(local)), o.T_parent_shape));
    manager_.registerObject(obstacles_.back().get());
  }
  manager_.setup();
  build_links();
}

FclWorld::FclWorld(const RobotModel& model, const OccupancyGrid& occupancy_W) : model_(model) {
  auto tree = std::make_shared<octomap::OcTree>(occupancy_W.resolution_m());
  const Eigen::Vector3i& n = occupancy_W.dims();
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        if (!occupancy_W.occupied(x, y, z)) continue;
        const Eigen::Vector3d c = occupancy_W.voxel_center_W(x, y, z);
        tree->updateNode(octomap::point3d(static_cast<float>(c.x()), static_cast<float>(c.y()), static_cast<float>(c.z())),
                         true, true);
      }
  tree->updateInnerOccupancy();
  octree_ = std::make_unique<fcl::CollisionObjectd>(std::make_shared<fcl::OcTreed>(tree));
  build_links();
}

void FclWorld::build_links() {
  for (const auto& link : model_.links) {
    TriangleMesh merged;
    for (const auto& s : link.shapes) {
      const TriangleMesh m = shape_to_mesh(s);  // in the link frame
      const int base = static_cast<int>(merged.vertices_m.size());
      merged.vertices_m.insert(merged.vertices_m.end(), m.vertices_m.begin(), m.vertices_m.end());
      for (const auto& t : m.triangles) merged.triangles.push_back(t + Eigen::Vector3i::Constant(base));
    }
    links_.push_back(merged.triangles.empty() ? nullptr : std::make_unique<fcl::CollisionObjectd>(mesh_to_fcl(merged)));
  }
}

namespace {
struct AnyCollision {
  bool hit = false;
};
bool any_collision_callback(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* data) {
  auto* d = static_cast<AnyCollision*>(data);
  fcl::CollisionRequestd req;
  fcl::CollisionResultd res;
  fcl::collide(a, b, req, res);
  d->hit = d->hit || res.isCollision();
  return d->hit;  // stop at the first contact
}
}  // namespace

bool FclWorld::in_collision(const RobotConfiguration& config) {
  KinematicsWorkspace ws;
  forward_kinematics(model_, config, ws);
  for (int k = 0; k < kNumLinks; ++k) {
    auto& obj = links_[static_cast<std::size_t>(k)];
    if (!obj) continue;
    obj->setTransform(ws.T_W_L[static_cast<std::size_t>(k)]);
    obj->computeAABB();
    if (octree_) {
      fcl::CollisionRequestd req;
      fcl::CollisionResultd res;
      fcl::collide(obj.get(), octree_.get(), req, res);
      if (res.isCollision()) return true;
      continue;
    }
    AnyCollision data;
    manager_.collide(obj.get(), &data, any_collision_callback);
    if (data.hit) return true;
  }
  for (int a = 0; a < kNumLinks; ++a)
    for (int b = a + 1; b < kNumLinks; ++b) {
      if (model_.allowed_collisions[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)]) continue;
      if (!links_[static_cast<std::size_t>(a)] || !links_[static_cast<std::size_t>(b)]) continue;
      fcl::CollisionRequestd req;
      fcl::CollisionResultd res;
      fcl::collide(links_[static_cast<std::size_t>(a)].get(), links_[static_cast<std::size_t>(b)].get(), req, res);
      if (res.isCollision()) return true;
    }
  return false;
}

// ---- ReferenceSelfCollision -------------------------------------------------------------------

struct ReferenceSelfCollision::Impl {
  struct Part {
    std::shared_ptr<fcl::CollisionGeometryd> geometry;
    Eigen::Isometry3d T_L_S;
  };
  std::array<std::vector<Part>, kNumLinks> parts;
};

ReferenceSelfCollision::ReferenceSelfCollision(const RobotModel& model)
    : model_(model), impl_(std::make_unique<Impl>()) {
  for (int k = 0; k < kNumLinks; ++k)
    for (const auto& s : model.links[static_cast<std::size_t>(k)].shapes)
      impl_->parts[static_cast<std::size_t>(k)].push_back({shape_to_fcl(s), s.T_parent_shape});
}

ReferenceSelfCollision::~ReferenceSelfCollision() = default;

bool ReferenceSelfCollision::pair_collides(const JointVector& q_rad, int a, int b) const {
  std::array<Eigen::Isometry3d, kNumLinks> T;
  arm_forward_kinematics(model_, q_rad, T);
  for (const auto& pa : impl_->parts[static_cast<std::size_t>(a)])
    for (const auto& pb : impl_->parts[static_cast<std::size_t>(b)]) {
      fcl::CollisionObjectd oa(pa.geometry, T[static_cast<std::size_t>(a)] * pa.T_L_S);
      fcl::CollisionObjectd ob(pb.geometry, T[static_cast<std::size_t>(b)] * pb.T_L_S);
      fcl::CollisionRequestd req;
      fcl::CollisionResultd res;
      fcl::collide(&oa, &ob, req, res);
      if (res.isCollision()) return true;
    }
  return false;
}

double ReferenceSelfCollision::pair_distance(const JointVector& q_rad, int a, int b) const {
  std::array<Eigen::Isometry3d, kNumLinks> T;
  arm_forward_kinematics(model_, q_rad, T);
  double best = std::numeric_limits<double>::infinity();
  for (const auto& pa : impl_->parts[static_cast<std::size_t>(a)])
    for (const auto& pb : impl_->parts[static_cast<std::size_t>(b)]) {
      fcl::CollisionObjectd oa(pa.geometry, T[static_cast<std::size_t>(a)] * pa.T_L_S);
      fcl::CollisionObjectd ob(pb.geometry, T[static_cast<std::size_t>(b)] * pb.T_L_S);
      fcl::DistanceRequestd req;
      req.enable_nearest_points = false;
      fcl::DistanceResultd res;
      fcl::distance(&oa, &ob, req, res);
      best = std::min(best, res.min_distance);
    }
  return best;
}

std::array<int, 2> ReferenceSelfCollision::first_colliding_pair(const JointVector& q_rad) const {
  for (int a = 0; a < kNumLinks; ++a)
    for (int b = a + 1; b < kNumLinks; ++b)
      if (!model_.allowed_collisions[static_cast<std::size_t>(a)][static_cast<std::size_t>(b)] &&
          pair_collides(q_rad, a, b))
        return {a, b};
  return {-1, -1};
}

}  // namespace porter::test
