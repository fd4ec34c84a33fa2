#include "fcl_world.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <variant>

namespace porter::validation {
namespace {

std::shared_ptr<fcl::CollisionGeometryd> to_fcl(const ShapeGeometry& geometry) {
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
          auto bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
          std::vector<fcl::Vector3d> v(g.mesh->vertices_m.begin(), g.mesh->vertices_m.end());
          std::vector<fcl::Triangle> t;
          t.reserve(g.mesh->triangles.size());
          for (const auto& tri : g.mesh->triangles)
            t.emplace_back(static_cast<std::size_t>(tri[0]), static_cast<std::size_t>(tri[1]),
                           static_cast<std::size_t>(tri[2]));
          bvh->beginModel();
          bvh->addSubModel(v, t);
          bvh->endModel();
          return bvh;
        }
      },
      geometry);
}

FclShape make_shape(int body, const std::string& name, const ShapeGeometry& g,
                    const Eigen::Isometry3d& T_body_shape) {
  FclShape s;
  s.body = body;
  s.name = name;
  s.geometry = g;
  s.T_body_shape = T_body_shape;
  s.object = std::make_unique<fcl::CollisionObjectd>(to_fcl(g), T_body_shape);
  s.object->computeAABB();
  s.aabb_W = s.object->getAABB();
  return s;
}

}  // namespace

double aabb_gap(const fcl::AABBd& a, const fcl::AABBd& b) {
  double sq = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double gap = std::max(a.min_[k] - b.max_[k], b.min_[k] - a.max_[k]);
    if (gap > 0.0) sq += gap * gap;
  }
  return std::sqrt(sq);
}

FclWorld::FclWorld(const RobotModel& model, const Payload& payload, const Scene& scene) {
  for (int l = 0; l < kNumLinks; ++l) {
    const Link& link = model.links[static_cast<size_t>(l)];
    for (size_t k = 0; k < link.shapes.size(); ++k) {
      const CollisionShape& cs = link.shapes[k];
      const std::string name = cs.name.empty() ? link.name + "[" + std::to_string(k) + "]" : cs.name;
      robot_.push_back(make_shape(l, name, cs.geometry, cs.T_parent_shape));
    }
  }
  for (size_t k = 0; k < payload.shapes.size(); ++k) {
    const CollisionShape& cs = payload.shapes[k];
    robot_.push_back(make_shape(kPayloadBody, "payload:" + payload.name + "/" + cs.name, cs.geometry,
                                payload.T_EE_P * cs.T_parent_shape));
  }
  for (const CollisionShape& o : scene.obstacles)
    obstacles_.push_back(make_shape(-1, o.name, o.geometry, o.T_parent_shape));
}

void FclWorld::place(const BodyPoses& T_W_body) {
  for (FclShape& s : robot_) {
    const Eigen::Isometry3d T = T_W_body[static_cast<size_t>(s.body)] * s.T_body_shape;
    s.object->setTransform(T.linear(), T.translation());
    s.object->computeAABB();
    s.aabb_W = s.object->getAABB();
  }
}

double FclWorld::contact_depth(const FclShape& a, const FclShape& b) {
  fcl::CollisionRequestd request(/*num_max_contacts=*/64, /*enable_contact=*/true);
  fcl::CollisionResultd result;
  fcl::collide(a.object.get(), b.object.get(), request, result);
  if (!result.isCollision()) return -1.0;
  double depth = 0.0;
  for (size_t i = 0; i < result.numContacts(); ++i)
    depth = std::max(depth, std::abs(result.getContact(i).penetration_depth));
  return depth;
}

double FclWorld::signed_distance(const FclShape& a, const FclShape& b) {
  fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  const double d = fcl::distance(a.object.get(), b.object.get(), request, result);
  if (d > 1e-9) return d;
  const double depth = contact_depth(a, b);
  if (depth < 0.0) return std::max(d, 0.0);  // touching within FCL's tolerance, no contact
  return -depth;
}

double FclWorld::lowest_z_W(const FclShape& s, const BodyPoses& T_W_body) const {
  const Eigen::Isometry3d T = T_W_body[static_cast<size_t>(s.body)] * s.T_body_shape;
  const Eigen::Vector3d c = T.translation();
  return std::visit(
      [&](const auto& g) -> double {
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, Box>) {
          // Half-extent along world z of a rotated box.
          const Eigen::Vector3d h = 0.5 * g.size_m;
          const Eigen::Vector3d row = T.linear().row(2).transpose();
          return c.z() - (row.cwiseAbs().cwiseProduct(h)).sum();
        } else if constexpr (std::is_same_v<G, Cylinder>) {
          const double az = std::abs(T.linear()(2, 2));
          return c.z() - 0.5 * g.length_m * az - g.radius_m * std::sqrt(std::max(0.0, 1.0 - az * az));
        } else if constexpr (std::is_same_v<G, Sphere>) {
          return c.z() - g.radius_m;
        } else {
          double z = std::numeric_limits<double>::infinity();
          for (const Eigen::Vector3d& v : g.mesh->vertices_m) z = std::min(z, (T * v).z());
          return z;
        }
      },
      s.geometry);
}

}  // namespace porter::validation
