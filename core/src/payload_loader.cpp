#include "porter/core/payload_loader.hpp"

#include "porter/core/load_error.hpp"
#include "porter/core/mesh_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter {

namespace {

Eigen::Vector3d read_scale(const yaml::Reader& r) {
  if (r.is_scalar()) {
    const double s = r.as_positive();
    return Eigen::Vector3d::Constant(s);
  }
  const Eigen::Vector3d s = r.as_vec3();
  if (!(s.array() > 0).all()) r.fail("every scale factor must be positive");
  return s;
}

CollisionShape read_primitive(const yaml::Reader& item) {
  const auto keys = item.keys();
  if (keys.size() != 1) item.fail("each shape is a map with exactly one key: box, cylinder or sphere");
  CollisionShape shape;
  shape.name = item.path();
  const auto body = item.get(keys[0]);
  if (keys[0] == "box") {
    body.expect_keys({"size", "pose"});
    const Eigen::Vector3d size = body.get("size").as_vec3();
    if (!(size.array() > 0).all()) body.get("size").fail("box sizes must be positive");
    shape.geometry = Box{size};
  } else if (keys[0] == "cylinder") {
    body.expect_keys({"radius", "length", "pose"});
    shape.geometry = Cylinder{body.get("radius").as_positive(), body.get("length").as_positive()};
  } else if (keys[0] == "sphere") {
    body.expect_keys({"radius", "pose"});
    shape.geometry = Sphere{body.get("radius").as_positive()};
  } else {
    item.fail("unknown shape '" + keys[0] + "' (box, cylinder or sphere)");
  }
  if (body.has("pose")) shape.T_parent_shape = body.get("pose").as_pose();
  return shape;
}

}  // namespace

Payload load_payload(const std::string& path) {
  const auto cfg = yaml::Reader::load_file(path);
  cfg.expect_keys({"name", "mesh", "shapes", "grasp"});
  Payload payload;
  payload.source = path;
  payload.name = cfg.get("name").as_string();
  if (cfg.has("mesh") == cfg.has("shapes"))
    throw LoadError(path, "", "give exactly one of 'mesh' and 'shapes'");
  if (cfg.has("mesh")) {
    const auto mesh = cfg.get("mesh");
    mesh.expect_keys({"file", "scale"});
    const std::string file = yaml::resolve_path(path, mesh.get("file").as_string());
    const Eigen::Vector3d scale = mesh.has("scale") ? read_scale(mesh.get("scale")) : Eigen::Vector3d::Ones();
    CollisionShape shape;
    shape.name = "mesh";
    try {
      shape.geometry = MeshShape{load_mesh(file, scale)};
    } catch (const LoadError& e) {
      throw LoadError(path, "key 'mesh.file'", e.what());
    }
    payload.shapes.push_back(std::move(shape));
  } else {
    const auto shapes = cfg.get("shapes");
    if (shapes.size() == 0) shapes.fail("needs at least one shape");
    for (std::size_t i = 0; i < shapes.size(); ++i) payload.shapes.push_back(read_primitive(shapes.at(i)));
  }
  payload.T_EE_P = cfg.get("grasp").as_pose();
  // The payload moves with the end effector: its extent sizes the planner's kernels and grids
  // like a link's (a 20 m sphere took 6.6 GB), so it obeys the same reach limit.
  const double grasp_offset = payload.T_EE_P.translation().norm();
  for (std::size_t i = 0; i < payload.shapes.size(); ++i) {
    const double reach = grasp_offset + shape_max_distance(payload.shapes[i], Eigen::Vector3d::Zero());
    if (!(reach <= kRobotMaxReach_m)) {
      const std::string key = cfg.has("mesh") ? "key 'mesh'" : "key 'shapes[" + std::to_string(i) + "]'";
      throw LoadError(path, key,
                      "reaches " + std::to_string(reach) + " m from the end effector (grasp offset included; limit " +
                          std::to_string(kRobotMaxReach_m) + " m)");
    }
  }
  return payload;
}

}  // namespace porter
