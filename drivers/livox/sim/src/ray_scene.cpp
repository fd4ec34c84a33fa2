#include "porter/livox_sim/ray_scene.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include <embree3/rtcore.h>

namespace porter::livox::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr unsigned kInvalid = RTC_INVALID_GEOMETRY_ID;

struct GeomInfo {
  HitKind kind = HitKind::none;
  int index = -1;
};

struct TriangleSoup {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<std::array<unsigned, 3>> triangles;
};

void add_box(const Box& box, const Eigen::Isometry3d& T, TriangleSoup& out) {
  const Eigen::Vector3d h = 0.5 * box.size_m;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d c((i & 1) ? h.x() : -h.x(), (i & 2) ? h.y() : -h.y(),
                            (i & 4) ? h.z() : -h.z());
    out.vertices.push_back((T * c).cast<float>());
  }
  static constexpr unsigned kFaces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6},
                                             {0, 1, 4}, {1, 5, 4}, {2, 6, 3}, {3, 6, 7},
                                             {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& f : kFaces) out.triangles.push_back({f[0], f[1], f[2]});
}

void add_cylinder(const Cylinder& cyl, const Eigen::Isometry3d& T, double tolerance_m,
                  TriangleSoup& out) {
  const double r = cyl.radius_m;
  const double tol = std::max(1e-6, tolerance_m);
  // Vertices at r_v, edge midpoints at r_v cos(pi/n); r_v = 2r / (1 + cos(pi/n)) puts the
  // two errors at +-r (1 - cos) / (1 + cos) <= tol.
  int n = 8;
  if (r > tol) {
    const double needed = kPi / std::acos(std::clamp((r - tol) / (r + tol), -1.0, 1.0));
    n = static_cast<int>(std::clamp(std::ceil(needed), 8.0, 1024.0));
  }
  const double c = std::cos(kPi / n);
  const double r_v = 2.0 * r / (1.0 + c);
  const double hz = 0.5 * cyl.length_m;
  for (int i = 0; i < n; ++i) {
    const double a = 2.0 * kPi * i / n;
    const double x = r_v * std::cos(a), y = r_v * std::sin(a);
    out.vertices.push_back((T * Eigen::Vector3d(x, y, -hz)).cast<float>());
    out.vertices.push_back((T * Eigen::Vector3d(x, y, hz)).cast<float>());
  }
  const unsigned bottom = static_cast<unsigned>(2 * n), top = bottom + 1;
  out.vertices.push_back((T * Eigen::Vector3d(0, 0, -hz)).cast<float>());
  out.vertices.push_back((T * Eigen::Vector3d(0, 0, hz)).cast<float>());
  for (int i = 0; i < n; ++i) {
    const unsigned b0 = 2 * i, t0 = 2 * i + 1;
    const unsigned b1 = 2 * ((i + 1) % n), t1 = b1 + 1;
    out.triangles.push_back({b0, b1, t1});
    out.triangles.push_back({b0, t1, t0});
    out.triangles.push_back({bottom, b1, b0});
    out.triangles.push_back({top, t0, t1});
  }
}

void add_mesh(const TriangleMesh& mesh, const Eigen::Isometry3d& T, TriangleSoup& out) {
  for (const auto& v : mesh.vertices_m) out.vertices.push_back((T * v).cast<float>());
  const auto nv = static_cast<int>(mesh.vertices_m.size());
  for (const auto& t : mesh.triangles) {
    if (t.minCoeff() < 0 || t.maxCoeff() >= nv) continue;  // a broken index is skipped
    out.triangles.push_back({static_cast<unsigned>(t[0]), static_cast<unsigned>(t[1]),
                             static_cast<unsigned>(t[2])});
  }
}

/// Attaches one shape (placed by T_scene_parent * shape.T_parent_shape) to `scene`; returns its
/// geometry id or kInvalid when it has no surface.
unsigned attach_shape(RTCDevice device, RTCScene scene, const CollisionShape& shape,
                      const Eigen::Isometry3d& T_scene_parent, double tolerance_m,
                      std::size_t& triangles) {
  const Eigen::Isometry3d T = T_scene_parent * shape.T_parent_shape;
  if (const auto* sphere = std::get_if<Sphere>(&shape.geometry)) {
    if (!(sphere->radius_m > 0.0)) return kInvalid;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
    if (v == nullptr) {
      rtcReleaseGeometry(g);
      return kInvalid;
    }
    const Eigen::Vector3d c = T.translation();
    v[0] = static_cast<float>(c.x());
    v[1] = static_cast<float>(c.y());
    v[2] = static_cast<float>(c.z());
    v[3] = static_cast<float>(sphere->radius_m);
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    return id;
  }
  TriangleSoup soup;
  std::visit(
      [&](const auto& geometry) {
        using G = std::decay_t<decltype(geometry)>;
        if constexpr (std::is_same_v<G, Box>) {
          add_box(geometry, T, soup);
        } else if constexpr (std::is_same_v<G, Cylinder>) {
          add_cylinder(geometry, T, tolerance_m, soup);
        } else if constexpr (std::is_same_v<G, MeshShape>) {
          if (geometry.mesh) add_mesh(*geometry.mesh, T, soup);
        }
      },
      shape.geometry);
  if (soup.triangles.empty()) return kInvalid;
  RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), soup.vertices.size()));
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), soup.triangles.size()));
  if (v == nullptr || idx == nullptr) {
    rtcReleaseGeometry(g);
    return kInvalid;
  }
  for (std::size_t i = 0; i < soup.vertices.size(); ++i) {
    v[3 * i] = soup.vertices[i].x();
    v[3 * i + 1] = soup.vertices[i].y();
    v[3 * i + 2] = soup.vertices[i].z();
  }
  for (std::size_t i = 0; i < soup.triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) idx[3 * i + k] = soup.triangles[i][k];
  }
  rtcCommitGeometry(g);
  const unsigned id = rtcAttachGeometry(scene, g);
  rtcReleaseGeometry(g);
  triangles += soup.triangles.size();
  return id;
}

void remember(std::vector<GeomInfo>& table, unsigned id, GeomInfo info) {
  if (id == kInvalid) return;
  if (table.size() <= id) table.resize(id + 1);
  table[id] = info;
}

struct Intersection {
  float t = -1.0f;
  unsigned geom = kInvalid;
  float cos_incidence = 0.0f;
};

Intersection intersect(RTCScene scene, const Eigen::Vector3f& o, const Eigen::Vector3f& d,
                       float t_near, float t_far) {
  Intersection result;
  // Embree asserts (aborts) on a ray it calls invalid: a non-finite origin or direction, a
  // negative or non-finite near distance. A pose gone non-finite upstream gives no return here
  // instead of ending the simulator.
  if (scene == nullptr || !(t_far >= t_near) || !(t_near >= 0.0f) || !std::isfinite(t_near) ||
      !o.allFinite() || !d.allFinite()) {
    return result;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh;
  rh.ray.org_x = o.x();
  rh.ray.org_y = o.y();
  rh.ray.org_z = o.z();
  rh.ray.tnear = t_near;
  rh.ray.dir_x = d.x();
  rh.ray.dir_y = d.y();
  rh.ray.dir_z = d.z();
  rh.ray.time = 0.0f;
  rh.ray.tfar = t_far;
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = kInvalid;
  rh.hit.instID[0] = kInvalid;
  rtcIntersect1(scene, &context, &rh);
  if (rh.hit.geomID == kInvalid) return result;
  result.t = rh.ray.tfar;
  result.geom = rh.hit.geomID;
  const Eigen::Vector3f n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  const float norm = n.norm();
  result.cos_incidence = norm > 0.0f ? std::fabs(n.dot(d)) / norm : 1.0f;
  return result;
}

}  // namespace

const char* to_string(HitKind kind) {
  switch (kind) {
    case HitKind::none: return "none";
    case HitKind::ground: return "ground";
    case HitKind::obstacle: return "obstacle";
    case HitKind::robot: return "robot";
    case HitKind::payload: return "payload";
  }
  return "unknown";
}

struct RayScene::Impl {
  struct LinkScene {
    RTCScene scene = nullptr;
    std::vector<GeomInfo> geoms;
    Eigen::Vector3f center_L = Eigen::Vector3f::Zero();
    float radius_m = 0.0f;
    Eigen::Matrix3f R_W_L = Eigen::Matrix3f::Identity();
    Eigen::Vector3f p_W_L = Eigen::Vector3f::Zero();
    Eigen::Vector3f center_W = Eigen::Vector3f::Zero();
  };

  RTCDevice device = nullptr;
  RTCScene world = nullptr;
  std::vector<GeomInfo> world_geoms;
  std::array<LinkScene, kNumLinks> links;

  ~Impl() {
    if (world) rtcReleaseScene(world);
    for (auto& l : links) {
      if (l.scene) rtcReleaseScene(l.scene);
    }
    if (device) rtcReleaseDevice(device);
  }
};

RayScene::RayScene(const RaySceneParams& params) : impl_(std::make_unique<Impl>()), params_(params) {
  // One build thread: the simulated sensor is meant to run on one core.
  impl_->device = rtcNewDevice("threads=1,set_affinity=0,verbose=0");
  if (impl_->device == nullptr) {
    error_ = "Embree: rtcNewDevice failed (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")";
    return;
  }
  set_obstacles({});
}

RayScene::~RayScene() = default;

void RayScene::set_obstacles(const std::vector<CollisionShape>& obstacles_W) {
  if (impl_->device == nullptr) return;
  if (impl_->world) rtcReleaseScene(impl_->world);
  impl_->world = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->world, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->world, RTC_BUILD_QUALITY_HIGH);
  impl_->world_geoms.clear();
  world_triangles_ = 0;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < obstacles_W.size(); ++i) {
    const unsigned id = attach_shape(impl_->device, impl_->world, obstacles_W[i], I,
                                     params_.tessellation_tolerance_m, world_triangles_);
    remember(impl_->world_geoms, id, {HitKind::obstacle, static_cast<int>(i)});
  }
  if (params_.ground_plane) {
    const double e = params_.ground_half_extent_m;
    CollisionShape ground;
    ground.geometry = Box{Eigen::Vector3d(2.0 * e, 2.0 * e, 0.0)};
    // A flat box: its top and bottom faces coincide with z = 0 (side faces have no area).
    const unsigned id = attach_shape(impl_->device, impl_->world, ground, I, 0.0, world_triangles_);
    remember(impl_->world_geoms, id, {HitKind::ground, -1});
  }
  rtcCommitScene(impl_->world);
  const RTCError e = rtcGetDeviceError(impl_->device);
  if (e != RTC_ERROR_NONE) error_ = "Embree: building the world scene failed (error " + std::to_string(e) + ")";
}

void RayScene::set_robot(const RobotModel& robot) {
  if (impl_->device == nullptr) return;
  robot_triangles_ = 0;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  for (int j = 0; j < kNumLinks; ++j) {
    auto& ls = impl_->links[j];
    if (ls.scene) rtcReleaseScene(ls.scene);
    ls.scene = nullptr;
    ls.geoms.clear();
    const Link& link = robot.links[j];
    if (link.shapes.empty()) continue;
    ls.scene = rtcNewScene(impl_->device);
    rtcSetSceneFlags(ls.scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(ls.scene, RTC_BUILD_QUALITY_HIGH);
    for (const CollisionShape& s : link.shapes) {
      const bool payload = s.name.rfind("payload '", 0) == 0;
      const unsigned id = attach_shape(impl_->device, ls.scene, s, I,
                                       params_.tessellation_tolerance_m, robot_triangles_);
      remember(ls.geoms, id, {payload ? HitKind::payload : HitKind::robot, j});
    }
    rtcCommitScene(ls.scene);
    ls.center_L = link.bounding_center.cast<float>();
    // Tessellated cylinders reach up to the tolerance beyond the true surface.
    ls.radius_m = static_cast<float>(link.bounding_radius_m + 2.0 * params_.tessellation_tolerance_m + 1e-4);
  }
  const RTCError e = rtcGetDeviceError(impl_->device);
  if (e != RTC_ERROR_NONE) error_ = "Embree: building the robot scenes failed (error " + std::to_string(e) + ")";
}

void RayScene::set_link_poses(const std::array<Eigen::Isometry3d, kNumLinks>& T_W_L) {
  for (int j = 0; j < kNumLinks; ++j) {
    auto& ls = impl_->links[j];
    ls.R_W_L = T_W_L[j].linear().cast<float>();
    ls.p_W_L = T_W_L[j].translation().cast<float>();
    ls.center_W = ls.R_W_L * ls.center_L + ls.p_W_L;
  }
}

RayHit RayScene::cast_world(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& unit_dir_W,
                            float t_near, float t_far) const {
  RayHit hit;
  const Intersection w = intersect(impl_->world, origin_W, unit_dir_W, t_near, t_far);
  if (w.geom != kInvalid && w.geom < impl_->world_geoms.size()) {
    hit.distance_m = w.t;
    hit.kind = impl_->world_geoms[w.geom].kind;
    hit.index = impl_->world_geoms[w.geom].index;
    hit.cos_incidence = w.cos_incidence;
  }
  return hit;
}

RayHit RayScene::cast(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& unit_dir_W,
                      float t_near, float t_far) const {
  RayHit best = cast_world(origin_W, unit_dir_W, t_near, t_far);
  float best_t = best.hit() ? best.distance_m : t_far;
  for (int j = 0; j < kNumLinks; ++j) {
    const auto& ls = impl_->links[j];
    if (ls.scene == nullptr) continue;
    const Eigen::Vector3f v = ls.center_W - origin_W;
    const float tca = v.dot(unit_dir_W);
    const float d2 = v.squaredNorm() - tca * tca;
    const float r2 = ls.radius_m * ls.radius_m;
    if (d2 > r2) continue;
    const float thc = std::sqrt(r2 - d2);
    if (tca + thc < t_near || tca - thc > best_t) continue;
    const Eigen::Vector3f o_L = ls.R_W_L.transpose() * (origin_W - ls.p_W_L);
    const Eigen::Vector3f d_L = ls.R_W_L.transpose() * unit_dir_W;
    const Intersection h = intersect(ls.scene, o_L, d_L, t_near, best_t);
    if (h.geom == kInvalid || h.geom >= ls.geoms.size()) continue;
    best_t = h.t;
    best.distance_m = h.t;
    best.kind = ls.geoms[h.geom].kind;
    best.index = ls.geoms[h.geom].index;
    best.cos_incidence = h.cos_incidence;
  }
  return best;
}

}  // namespace porter::livox::sim
