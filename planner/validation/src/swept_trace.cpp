#include "porter/validation/swept_trace.hpp"

#include <type_traits>
#include <variant>

#include <nlohmann/json.hpp>

#include "porter/validation/validator.hpp"

namespace porter::validation {
namespace {

using nlohmann::json;

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

json obstacle_json(const CollisionShape& o) {
  json j{{"name", o.name}};
  json T = json::array();
  for (int r = 0; r < 4; ++r) {
    json row = json::array();
    for (int c = 0; c < 4; ++c) row.push_back(o.T_parent_shape.matrix()(r, c));
    T.push_back(row);
  }
  j["T_W_shape"] = T;
  std::visit(
      [&](const auto& g) {
        using G = std::decay_t<decltype(g)>;
        if constexpr (std::is_same_v<G, Box>) {
          j["kind"] = "box";
          j["size"] = vec(g.size_m);
        } else if constexpr (std::is_same_v<G, Cylinder>) {
          j["kind"] = "cylinder";
          j["radius"] = g.radius_m;
          j["length"] = g.length_m;
        } else if constexpr (std::is_same_v<G, Sphere>) {
          j["kind"] = "sphere";
          j["radius"] = g.radius_m;
        } else {
          j["kind"] = "mesh";
          const Eigen::AlignedBox3d b = g.mesh->bounds();
          j["bounds_min"] = vec(b.min());
          j["bounds_max"] = vec(b.max());
        }
      },
      o.geometry);
  return j;
}

}  // namespace

std::string swept_trace_json(const RobotModel& model, const Payload& payload, const Scene& scene,
                             const FlatTrajectory& trajectory, double payload_spacing_m) {
  json doc;
  doc["format"] = "porter-validate-trace/1";
  doc["scene"] = scene.name;
  doc["bounds"] = {{"min", vec(scene.bounds_W.min())}, {"max", vec(scene.bounds_W.max())}};
  json obstacles = json::array();
  for (const auto& o : scene.obstacles) obstacles.push_back(obstacle_json(o));
  doc["obstacles"] = obstacles;

  // The payload as triangles in the EE frame.
  std::vector<TriangleMesh> meshes;
  for (CollisionShape s : payload.shapes) {
    s.T_parent_shape = payload.T_EE_P * s.T_parent_shape;
    meshes.push_back(shape_to_mesh(s, 16));
  }
  ValidationSettings settings;
  settings.max_step_m = 0.02;
  json base = json::array(), swept = json::array();
  Eigen::Vector3d last_center(1e9, 1e9, 1e9);
  const auto times = sample_times(model, payload, trajectory, settings, nullptr);
  for (size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];
    const WholeBodyConfig c = config_at(trajectory, t);
    base.push_back(json::array({t, c.x_m, c.y_m, c.yaw_rad}));
    const BodyPoses T = body_poses(model, c);
    const Eigen::Isometry3d& T_W_EE = T[kPayloadBody];
    const Eigen::Vector3d center = T_W_EE * payload.T_EE_P.translation();
    if ((center - last_center).norm() < payload_spacing_m && i + 1 != times.size()) continue;
    last_center = center;
    json tris = json::array();
    for (const auto& m : meshes)
      for (const auto& tri : m.triangles)
        tris.push_back(json::array({vec(T_W_EE * m.vertices_m[static_cast<size_t>(tri[0])]),
                                    vec(T_W_EE * m.vertices_m[static_cast<size_t>(tri[1])]),
                                    vec(T_W_EE * m.vertices_m[static_cast<size_t>(tri[2])])}));
    swept.push_back({{"t_s", t}, {"triangles", tris}});
  }
  doc["base"] = base;
  doc["payload"] = swept;
  return doc.dump();
}

}  // namespace porter::validation
