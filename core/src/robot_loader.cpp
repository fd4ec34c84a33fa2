#include "porter/core/robot_loader.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <sstream>
#include <set>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "porter/core/load_error.hpp"
#include "porter/core/mesh_loader.hpp"
#include "porter/core/yaml_reader.hpp"

namespace porter {

namespace {

Eigen::Isometry3d to_eigen(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  return T;
}

Eigen::Vector3d to_eigen(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

std::string fmt(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// An origin must be finite, within kRobotMaxReach_m, with a quaternion that can be normalised.
void check_pose(const urdf::Pose& p, const std::string& urdf_path, const std::string& element) {
  const Eigen::Vector3d xyz = to_eigen(p.position);
  const Eigen::Vector4d q(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z);
  if (!xyz.allFinite() || !q.allFinite())
    throw LoadError(urdf_path, element, "origin is not finite");
  if (xyz.norm() > kRobotMaxReach_m)
    throw LoadError(urdf_path, element,
                    "origin is " + fmt(xyz.norm()) + " m from its parent (limit " + fmt(kRobotMaxReach_m) + " m)");
  if (!(q.norm() > 1e-6)) throw LoadError(urdf_path, element, "origin rotation is degenerate");
}

// A size of robot geometry: finite, > 0 and at most kRobotMaxReach_m.
void check_size(double v, const std::string& urdf_path, const std::string& element, const char* what) {
  if (!std::isfinite(v) || !(v > 0.0) || v > kRobotMaxReach_m)
    throw LoadError(urdf_path, element,
                    std::string(what) + " must be finite, > 0 and at most " + fmt(kRobotMaxReach_m) + " m (got " +
                        fmt(v) + ")");
}

// urdfdom reports why it refused a file through console_bridge; this collects it while one
// parse runs. console_bridge's handler is process-wide, so parses are serialised.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) {
      if (errors_.size() < 4096) errors_ += (errors_.empty() ? "" : "; ") + text;
    }
  }
  const std::string& errors() const { return errors_; }

 private:
  std::string errors_;
};

urdf::ModelInterfaceSharedPtr parse_urdf(const std::string& urdf_path, std::string* reason) {
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  CapturedLog captured;
  const console_bridge::LogLevel level = console_bridge::getLogLevel();
  console_bridge::useOutputHandler(&captured);
  console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDFFile(urdf_path);
  } catch (const std::exception& e) {
    captured.log(e.what(), console_bridge::CONSOLE_BRIDGE_LOG_ERROR, "", 0);
  }
  console_bridge::restorePreviousOutputHandler();
  console_bridge::setLogLevel(level);
  // urdfdom logs an error and drops the element when, e.g., a collision's size does not parse
  // ("nan"), yet returns a model: a logged error refuses the file.
  *reason = captured.errors();
  if (!reason->empty()) model.reset();
  return model;
}

const char* joint_type_name(int type) {
  switch (type) {
    case urdf::Joint::REVOLUTE: return "revolute";
    case urdf::Joint::CONTINUOUS: return "continuous";
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::FLOATING: return "floating";
    case urdf::Joint::PLANAR: return "planar";
    case urdf::Joint::FIXED: return "fixed";
    default: return "unknown";
  }
}

// Motion of a movable joint held at a fixed value (frozen joints).
Eigen::Isometry3d frozen_motion(const urdf::Joint& joint, double value) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d axis = to_eigen(joint.axis).normalized();
  if (joint.type == urdf::Joint::PRISMATIC) {
    T.translation() = axis * value;
  } else {
    T.linear() = Eigen::AngleAxisd(value, axis).toRotationMatrix();
  }
  return T;
}

std::string resolve_mesh_uri(const std::string& urdf_path, const std::string& uri) {
  const std::string element = "mesh filename '" + uri + "'";
  if (uri.rfind("package://", 0) == 0)
    throw LoadError(urdf_path, element,
                    "package:// URIs need a ROS package path; give a path relative to the URDF");
  std::string path = uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
  return yaml::resolve_path(urdf_path, path);
}

CollisionShape convert_collision(const urdf::Collision& col, const std::string& urdf_path,
                                 const std::string& link_name, std::size_t index,
                                 const Eigen::Isometry3d& T_planning_link) {
  CollisionShape shape;
  shape.name = link_name + "/collision[" + std::to_string(index) + "]";
  const std::string element = "link '" + link_name + "' collision[" + std::to_string(index) + "]";
  check_pose(col.origin, urdf_path, element);
  shape.T_parent_shape = T_planning_link * to_eigen(col.origin);
  const urdf::Geometry* g = col.geometry.get();
  if (g == nullptr) throw LoadError(urdf_path, "link '" + link_name + "'", "collision without geometry");
  switch (g->type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(*g);
      check_size(b.dim.x, urdf_path, element, "box size x");
      check_size(b.dim.y, urdf_path, element, "box size y");
      check_size(b.dim.z, urdf_path, element, "box size z");
      shape.geometry = Box{to_eigen(b.dim)};
      break;
    }
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(*g);
      check_size(c.radius, urdf_path, element, "cylinder radius");
      check_size(c.length, urdf_path, element, "cylinder length");
      shape.geometry = Cylinder{c.radius, c.length};
      break;
    }
    case urdf::Geometry::SPHERE: {
      check_size(static_cast<const urdf::Sphere&>(*g).radius, urdf_path, element, "sphere radius");
      shape.geometry = Sphere{static_cast<const urdf::Sphere&>(*g).radius};
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(*g);
      const Eigen::Vector3d scale = to_eigen(m.scale);
      if (!scale.allFinite() || !(scale.array() > 0.0).all())
        throw LoadError(urdf_path, element, "mesh scale must be finite and > 0 on every axis");
      const std::string path = resolve_mesh_uri(urdf_path, m.filename);
      try {
        shape.geometry = MeshShape{load_mesh(path, to_eigen(m.scale))};
      } catch (const LoadError& e) {
        throw LoadError(urdf_path, "link '" + link_name + "' mesh '" + m.filename + "'", e.what());
      }
      break;
    }
    default:
      throw LoadError(urdf_path, "link '" + link_name + "'", "unsupported collision geometry type");
  }
  // Every point within kRobotMaxReach_m of the link frame: the planner's kernels and distance
  // grids are sized from this extent (a 1e9 m box overflowed an int there).
  const double reach = shape_max_distance(shape, Eigen::Vector3d::Zero());
  if (!(reach <= kRobotMaxReach_m))
    throw LoadError(urdf_path, element,
                    "reaches " + fmt(reach) + " m from its planning link's frame (limit " + fmt(kRobotMaxReach_m) +
                        " m)");
  return shape;
}

// A positive parameter within [lo, hi] (the ranges are in robot_loader.hpp).
void read_in_range(const yaml::Reader& r, const char* key, double lo, double hi, double& out) {
  const yaml::Reader v = r.get(key);
  out = v.as_double();
  if (!(out >= lo && out <= hi)) v.fail("must be within [" + fmt(lo) + ", " + fmt(hi) + "], got " + fmt(out));
}

}  // namespace

RobotModel load_robot_model(const std::string& robot_yaml_path) {
  const auto cfg = yaml::Reader::load_file(robot_yaml_path);
  cfg.expect_keys({"name", "urdf", "base_link", "arm_joints", "end_effector", "frozen_joints",
                   "joint_acceleration_max_radps2", "base", "allowed_collisions"});

  RobotModel model;
  model.source = robot_yaml_path;
  model.name = cfg.get("name").as_string();
  const std::string urdf_path = yaml::resolve_path(robot_yaml_path, cfg.get("urdf").as_string());
  const std::string base_link = cfg.get("base_link").as_string();
  const auto arm_joint_names = cfg.get("arm_joints").as_strings();
  if (arm_joint_names.size() != static_cast<std::size_t>(kNumArmJoints))
    cfg.get("arm_joints").fail("Porter plans for arms with exactly " + std::to_string(kNumArmJoints) +
                               " revolute joints; " + std::to_string(arm_joint_names.size()) + " listed");
  const auto ee = cfg.get("end_effector");
  ee.expect_keys({"link", "frame"});
  const std::string ee_link = ee.get("link").as_string();
  const std::string ee_frame = ee.get("frame").as_string();

  std::map<std::string, double> frozen;
  {
    const auto fj = cfg.get("frozen_joints");
    if (!fj.node().IsNull())
      for (const auto& key : fj.keys()) {
        frozen[key] = fj.get(key).as_double();
        if (std::abs(frozen[key]) > 1e3) fj.get(key).fail("must be within +-1000 (rad or m), got " + fmt(frozen[key]));
      }
  }
  const auto accel = cfg.get("joint_acceleration_max_radps2").as_doubles(kNumArmJoints);
  for (std::size_t i = 0; i < accel.size(); ++i)
    if (!(accel[i] > 0 && accel[i] <= 1e4))
      cfg.get("joint_acceleration_max_radps2").at(i).fail("must be within (0, 10000], got " + fmt(accel[i]));

  const auto base = cfg.get("base");
  base.expect_keys({"wheel_radius_m", "track_width_m", "wheel_omega_max_radps", "wheel_alpha_max_radps2",
                    "min_turning_radius_m", "nonsingular_speed_mps"});
  read_in_range(base, "wheel_radius_m", 1e-3, 2.0, model.base.wheel_radius_m);
  read_in_range(base, "track_width_m", 1e-2, 10.0, model.base.track_width_m);
  read_in_range(base, "wheel_omega_max_radps", 1e-3, 1e3, model.base.wheel_omega_max_radps);
  read_in_range(base, "wheel_alpha_max_radps2", 1e-3, 1e4, model.base.wheel_alpha_max_radps2);
  read_in_range(base, "min_turning_radius_m", 1e-3, 100.0, model.base.min_turning_radius_m);
  read_in_range(base, "nonsingular_speed_mps", 1e-4, 10.0, model.base.nonsingular_speed_mps);

  // --- URDF ---------------------------------------------------------------------------------
  if (!std::filesystem::exists(urdf_path))
    throw LoadError(robot_yaml_path, "key 'urdf'", "URDF file not found: " + urdf_path);
  if (!std::filesystem::is_regular_file(urdf_path))
    throw LoadError(robot_yaml_path, "key 'urdf'", "not a regular file: " + urdf_path);
  if (std::filesystem::file_size(urdf_path) > yaml::Reader::kMaxFileBytes)
    throw LoadError(urdf_path, "", "URDF larger than " + std::to_string(yaml::Reader::kMaxFileBytes) + " bytes");
  std::string urdfdom_reason;
  const urdf::ModelInterfaceSharedPtr urdf_model = parse_urdf(urdf_path, &urdfdom_reason);
  if (!urdf_model)
    throw LoadError(urdf_path, "", "not a valid URDF: " +
                                       (urdfdom_reason.empty() ? std::string("urdfdom gave no reason") : urdfdom_reason));

  const urdf::LinkConstSharedPtr root = urdf_model->getRoot();
  if (!root || root->name != base_link)
    throw LoadError(urdf_path, "link '" + base_link + "'",
                    "base_link must be the URDF root (root is '" + (root ? root->name : "") + "')");
  for (const char* name : {ee_link.c_str(), ee_frame.c_str()})
    if (!urdf_model->getLink(name))
      throw LoadError(robot_yaml_path, "key 'end_effector'", std::string("no link '") + name + "' in " + urdf_path);

  std::map<std::string, int> arm_index;
  for (int i = 0; i < kNumArmJoints; ++i) {
    const auto joint = urdf_model->getJoint(arm_joint_names[i]);
    if (!joint) throw LoadError(urdf_path, "joint '" + arm_joint_names[i] + "'", "arm joint not found in the URDF");
    if (joint->type != urdf::Joint::REVOLUTE)
      throw LoadError(urdf_path, "joint '" + arm_joint_names[i] + "'",
                      std::string("unsupported joint: arm joints must be revolute with limits, this one is ") +
                          joint_type_name(joint->type));
    if (!joint->limits || !(joint->limits->upper > joint->limits->lower) || !(joint->limits->velocity > 0))
      throw LoadError(urdf_path, "joint '" + arm_joint_names[i] + "'",
                      "needs <limit> with lower < upper and velocity > 0");
    if (!(std::abs(joint->limits->lower) <= kRobotMaxJointAngle_rad) ||
        !(std::abs(joint->limits->upper) <= kRobotMaxJointAngle_rad) ||
        !(joint->limits->velocity <= kRobotMaxJointVelocity_radps))
      throw LoadError(urdf_path, "joint '" + arm_joint_names[i] + "'",
                      "limits must be within +-" + fmt(kRobotMaxJointAngle_rad) + " rad and velocity at most " +
                          fmt(kRobotMaxJointVelocity_radps) + " rad/s (got [" + fmt(joint->limits->lower) + ", " +
                          fmt(joint->limits->upper) + "], " + fmt(joint->limits->velocity) + ")");
    arm_index[arm_joint_names[i]] = i;
  }
  for (const auto& [name, value] : frozen) {
    const auto joint = urdf_model->getJoint(name);
    if (!joint) throw LoadError(robot_yaml_path, "key 'frozen_joints." + name + "'", "no such joint in " + urdf_path);
    if (arm_index.count(name))
      throw LoadError(robot_yaml_path, "key 'frozen_joints." + name + "'", "an arm joint cannot be frozen");
  }

  // Walk the tree: planning link index and pose of each URDF link in its chain link's frame
  // (links under the end effector are re-expressed in the EE frame afterwards).
  std::map<std::string, int> chain_of;
  std::map<std::string, Eigen::Isometry3d, std::less<>> T_chain_link;
  std::map<std::string, bool> under_ee;
  std::function<void(const urdf::LinkConstSharedPtr&)> visit = [&](const urdf::LinkConstSharedPtr& link) {
    for (const auto& child_joint : link->child_joints) {
      const std::string child = child_joint->child_link_name;
      const std::string element = "joint '" + child_joint->name + "'";
      const int parent_chain = chain_of[link->name];
      check_pose(child_joint->parent_to_joint_origin_transform, urdf_path, element);
      if (child_joint->type == urdf::Joint::REVOLUTE || child_joint->type == urdf::Joint::CONTINUOUS ||
          child_joint->type == urdf::Joint::PRISMATIC) {
        const Eigen::Vector3d axis = to_eigen(child_joint->axis);
        if (!axis.allFinite() || !(axis.norm() > 1e-9))
          throw LoadError(urdf_path, element, "axis must be a finite non-zero vector (got [" + fmt(axis.x()) + " " +
                                                  fmt(axis.y()) + " " + fmt(axis.z()) + "])");
      }
      Eigen::Isometry3d T = T_chain_link[link->name] * to_eigen(child_joint->parent_to_joint_origin_transform);
      const auto arm = arm_index.find(child_joint->name);
      if (arm != arm_index.end()) {
        if (under_ee[link->name])
          throw LoadError(robot_yaml_path, "key 'end_effector.link'",
                          "arm joint '" + child_joint->name + "' lies below the end effector link '" + ee_link +
                              "'; the end effector must come after the last arm joint");
        if (parent_chain != arm->second)
          throw LoadError(urdf_path, element,
                          "broken chain: arm joint " + std::to_string(arm->second + 1) + " is attached to link '" +
                              link->name + "', which is not downstream of arm joint " + std::to_string(arm->second));
        ArmJoint& aj = model.joints[arm->second];
        aj.name = child_joint->name;
        aj.T_parent_joint = T;
        aj.axis = to_eigen(child_joint->axis).normalized();
        aj.lower_rad = child_joint->limits->lower;
        aj.upper_rad = child_joint->limits->upper;
        aj.velocity_max_radps = child_joint->limits->velocity;
        aj.acceleration_max_radps2 = accel[arm->second];
        chain_of[child] = arm->second + 1;
        T_chain_link[child] = Eigen::Isometry3d::Identity();
      } else {
        switch (child_joint->type) {
          case urdf::Joint::FIXED:
            break;
          case urdf::Joint::REVOLUTE:
          case urdf::Joint::CONTINUOUS:
          case urdf::Joint::PRISMATIC: {
            const auto f = frozen.find(child_joint->name);
            if (f == frozen.end())
              throw LoadError(urdf_path, element,
                              std::string("unsupported joint: movable (") + joint_type_name(child_joint->type) +
                                  ") but not an arm joint; list it under frozen_joints in " + robot_yaml_path);
            T = T * frozen_motion(*child_joint, f->second);
            break;
          }
          default:
            throw LoadError(urdf_path, element,
                            std::string("unsupported joint type: ") + joint_type_name(child_joint->type));
        }
        chain_of[child] = parent_chain;
        T_chain_link[child] = T;
      }
      under_ee[child] = under_ee[link->name] || child == ee_link;
      visit(urdf_model->getLink(child));
    }
  };
  chain_of[root->name] = 0;
  T_chain_link[root->name] = Eigen::Isometry3d::Identity();
  under_ee[root->name] = root->name == ee_link;
  visit(root);

  for (int i = 0; i < kNumArmJoints; ++i)
    if (model.joints[i].name.empty())
      throw LoadError(urdf_path, "joint '" + arm_joint_names[i] + "'", "broken chain: not reachable from the root");
  if (!under_ee[ee_link] || chain_of[ee_link] != kNumArmJoints)
    throw LoadError(robot_yaml_path, "key 'end_effector.link'",
                    "'" + ee_link + "' must be downstream of the last arm joint through fixed joints");
  if (!under_ee[ee_frame])
    throw LoadError(robot_yaml_path, "key 'end_effector.frame'",
                    "'" + ee_frame + "' must be '" + ee_link + "' or one of its descendants");

  model.T_L6_EE = T_chain_link[ee_frame];
  const Eigen::Isometry3d T_EE_L6 = model.T_L6_EE.inverse();

  model.links[0].name = base_link;
  for (int j = 1; j <= kNumArmJoints; ++j)
    model.links[j].name = urdf_model->getJoint(arm_joint_names[j - 1])->child_link_name;
  model.links[kEndEffectorLink].name = ee_frame;

  std::vector<urdf::LinkSharedPtr> all_links;
  urdf_model->getLinks(all_links);
  std::sort(all_links.begin(), all_links.end(), [](const auto& a, const auto& b) { return a->name < b->name; });
  for (const auto& link : all_links) {
    const bool ee = under_ee[link->name];
    const int index = ee ? kEndEffectorLink : chain_of[link->name];
    const Eigen::Isometry3d T = ee ? T_EE_L6 * T_chain_link[link->name] : T_chain_link[link->name];
    std::size_t k = 0;
    for (const auto& col : link->collision_array)
      if (col) model.links[index].shapes.push_back(convert_collision(*col, urdf_path, link->name, k++, T));
    if (link->collision_array.empty() && link->collision)
      model.links[index].shapes.push_back(convert_collision(*link->collision, urdf_path, link->name, 0, T));
  }

  // Neighbours along the chain touch by construction; every other pair is checked.
  for (int a = 0; a < kNumLinks; ++a)
    for (int b = 0; b < kNumLinks; ++b) model.allowed_collisions[a][b] = std::abs(a - b) <= 1;
  if (cfg.has("allowed_collisions")) {
    const auto pairs = cfg.get("allowed_collisions");
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      const auto pair = pairs.at(i).as_doubles(2);
      const int a = static_cast<int>(pair[0]), b = static_cast<int>(pair[1]);
      if (a < 0 || b < 0 || a >= kNumLinks || b >= kNumLinks || a != pair[0] || b != pair[1])
        pairs.at(i).fail("link indices must be integers in 0.." + std::to_string(kNumLinks - 1));
      model.allowed_collisions[a][b] = model.allowed_collisions[b][a] = true;
    }
  }
  model.update_link_bounds();
  return model;
}

}  // namespace porter
