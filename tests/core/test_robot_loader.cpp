// The shipped robot loads as designed; every loader error path names the file, the element and
// the reason.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "porter/core/load_error.hpp"
#include "porter/core/robot_loader.hpp"
#include "robot_test_utils.hpp"

namespace porter {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture text not found: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

class RobotLoaderTest : public ::testing::Test {
 protected:
  RobotLoaderTest() : dir_("robot_loader") {
    urdf_ = read(test::source_dir() + "/config/robots/scout_mini_piper/scout_mini_piper.urdf");
    yaml_ = read(test::robot_yaml());
  }
  // Writes the (possibly edited) URDF and YAML to scratch files and loads them.
  RobotModel load(const std::string& urdf, const std::string& yaml) {
    dir_.file("scout_mini_piper.urdf", urdf);
    return load_robot_model(dir_.file("robot.yaml", yaml));
  }
  // Expects a LoadError whose message contains every fragment.
  void expect_error(const std::string& urdf, const std::string& yaml, std::vector<std::string> fragments) {
    try {
      load(urdf, yaml);
      ADD_FAILURE() << "expected a LoadError containing '" << fragments.front() << "'";
    } catch (const LoadError& e) {
      for (const auto& f : fragments) EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << e.what();
    }
  }
  test::ScratchDir dir_;
  std::string urdf_, yaml_;
};

TEST_F(RobotLoaderTest, ShippedRobotHasTheDesignedChain) {
  const RobotModel m = load_robot_model(test::robot_yaml());
  EXPECT_EQ(m.name, "scout_mini_piper");
  EXPECT_EQ(m.links[0].name, "base_link");
  EXPECT_EQ(m.links[6].name, "link6");
  EXPECT_EQ(m.links[7].name, "grasp_frame");
  // Base: chassis + 4 wheels + mast (2) + arm casing (1) all belong to link 0.
  EXPECT_EQ(m.links[0].shapes.size(), 8u);
  // Gripper body and two fingers move with the payload.
  EXPECT_EQ(m.links[7].shapes.size(), 3u);
  for (int j = 1; j <= 6; ++j) EXPECT_FALSE(m.links[j].shapes.empty()) << j;
  // SDK joint limits (rad), not the vendor URDF's wider J4/J6.
  EXPECT_DOUBLE_EQ(m.joints[3].upper_rad, 1.745);
  EXPECT_DOUBLE_EQ(m.joints[5].lower_rad, -2.09439);
  EXPECT_DOUBLE_EQ(m.joints[1].lower_rad, 0.0);
  EXPECT_DOUBLE_EQ(m.joints[2].upper_rad, 0.0);
  EXPECT_DOUBLE_EQ(m.joints[0].acceleration_max_radps2, 3.0);
  EXPECT_DOUBLE_EQ(m.base.track_width_m, 0.4165);
  EXPECT_TRUE(m.allowed_collisions[3][4]);
  EXPECT_FALSE(m.allowed_collisions[0][2]);
  EXPECT_FALSE(m.allowed_collisions[7][5]);
  // Bounding balls contain every link's bounds: the base is the Scout body (~0.66 m diagonal half).
  EXPECT_GT(m.links[0].bounding_radius_m, 0.3);
  EXPECT_LT(m.links[0].bounding_radius_m, 0.6);
  // Every vertex of every shape's triangulation lies inside its link's bounding ball.
  for (const auto& link : m.links)
    for (const auto& shape : link.shapes)
      for (const auto& v : shape_to_mesh(shape).vertices_m)
        EXPECT_LE((v - link.bounding_center).norm(), link.bounding_radius_m + 1e-9) << shape.name;
}

TEST_F(RobotLoaderTest, MissingRobotYaml) {
  try {
    load_robot_model(dir_.path("nope.yaml"));
    FAIL();
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("nope.yaml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos);
  }
}

TEST_F(RobotLoaderTest, UnknownAndMissingKeys) {
  expect_error(urdf_, yaml_ + "\nextra_key: 1\n", {"robot.yaml", "extra_key", "unknown key"});
  expect_error(urdf_, replace(yaml_, "name: scout_mini_piper\n", ""), {"robot.yaml", "'name'", "missing"});
  expect_error(urdf_, replace(yaml_, "wheel_radius_m: 0.0875", "wheel_radius_m: -1"),
               {"base.wheel_radius_m", "must be within [0.001, 2], got -1"});
  expect_error(urdf_, replace(yaml_, "wheel_radius_m: 0.0875", "wheel_radius_m: fast"),
               {"base.wheel_radius_m", "expected a number"});
  expect_error(urdf_, replace(yaml_, "[3.0, 3.0, 3.0, 4.0, 4.0, 4.0]", "[3.0, 3.0]"),
               {"joint_acceleration_max_radps2", "6 numbers"});
}

TEST_F(RobotLoaderTest, MissingUrdfAndUnparsableUrdf) {
  expect_error(urdf_, replace(yaml_, "urdf: scout_mini_piper.urdf", "urdf: missing.urdf"),
               {"'urdf'", "not found", "missing.urdf"});
  expect_error("<robot name='x'><link name=", yaml_, {"scout_mini_piper.urdf", "not a valid URDF"});
}

TEST_F(RobotLoaderTest, ArmJointMissingOrWrongType) {
  expect_error(urdf_, replace(yaml_, "joint6]", "joint7]"), {"joint7", "not found"});
  expect_error(replace(urdf_, "name=\"joint3\" type=\"revolute\"", "name=\"joint3\" type=\"continuous\""), yaml_,
               {"joint 'joint3'", "unsupported joint", "continuous"});
  expect_error(urdf_, replace(yaml_, "[joint1, joint2, joint3, joint4, joint5, joint6]", "[joint1, joint2]"),
               {"arm_joints", "exactly 6"});
}

TEST_F(RobotLoaderTest, BrokenChainOrder) {
  // Listing the joints out of order means joint 3 hangs from a link that is not downstream of joint 2.
  expect_error(urdf_,
               replace(yaml_, "[joint1, joint2, joint3, joint4, joint5, joint6]",
                       "[joint1, joint3, joint2, joint4, joint5, joint6]"),
               {"broken chain"});
}

TEST_F(RobotLoaderTest, MovableNonArmJointMustBeFrozen) {
  const std::string urdf = replace(urdf_, "name=\"mast_mount\" type=\"fixed\"", "name=\"mast_mount\" type=\"prismatic\"");
  const std::string with_limit =
      replace(urdf, "<child link=\"lidar_mast\"/>",
              "<child link=\"lidar_mast\"/><axis xyz=\"0 0 1\"/><limit lower=\"0\" upper=\"0.2\" velocity=\"1\" effort=\"1\"/>");
  expect_error(with_limit, yaml_, {"mast_mount", "frozen_joints"});
  // Frozen at 0.1 m: the mast's geometry moves up by 0.1 m.
  const RobotModel m = load(with_limit, replace(yaml_, "frozen_joints: {}", "frozen_joints: {mast_mount: 0.1}"));
  const RobotModel ref = load_robot_model(test::robot_yaml());
  EXPECT_NEAR(m.links[0].bounds.max().z() - ref.links[0].bounds.max().z(), 0.1, 1e-12);
}

TEST_F(RobotLoaderTest, FloatingJointIsUnsupported) {
  const std::string urdf = replace(urdf_, "name=\"mast_mount\" type=\"fixed\"", "name=\"mast_mount\" type=\"floating\"");
  expect_error(urdf, replace(yaml_, "frozen_joints: {}", "frozen_joints: {}"), {"mast_mount", "unsupported joint"});
}

TEST_F(RobotLoaderTest, BaseLinkMustBeRoot) {
  expect_error(urdf_, replace(yaml_, "base_link: base_link", "base_link: link1"), {"base_link must be the URDF root"});
}

TEST_F(RobotLoaderTest, EndEffectorMustBeDownstreamOfTheArm) {
  expect_error(urdf_, replace(yaml_, "link: gripper_base", "link: link3"), {"end_effector.link"});
  expect_error(urdf_, replace(yaml_, "frame: grasp_frame", "frame: nowhere"), {"end_effector", "nowhere"});
}

TEST_F(RobotLoaderTest, MeshGeometryLoadsAndBadMeshesAreReported) {
  // Swap the flange cylinder for the T-bar mesh (any mesh will do) with a scale.
  const std::string mesh_path = test::source_dir() + "/config/payloads/meshes/t_bar.stl";
  const std::string flange = "<cylinder radius=\"0.035\" length=\"0.02\"/>";
  const RobotModel m = load(replace(urdf_, flange, "<mesh filename=\"file://" + mesh_path + "\" scale=\"0.1 0.1 0.1\"/>"), yaml_);
  ASSERT_EQ(m.links[6].shapes.size(), 1u);
  ASSERT_TRUE(std::holds_alternative<MeshShape>(m.links[6].shapes[0].geometry));
  EXPECT_NEAR(std::get<MeshShape>(m.links[6].shapes[0].geometry).mesh->bounds().sizes().maxCoeff(), 0.1, 1e-6);

  expect_error(replace(urdf_, flange, "<mesh filename=\"missing.stl\"/>"), yaml_, {"link6", "missing.stl", "not found"});
  dir_.file("garbage.stl", "this is not a mesh at all\n");
  expect_error(replace(urdf_, flange, "<mesh filename=\"garbage.stl\"/>"), yaml_, {"link6", "garbage.stl"});
  expect_error(replace(urdf_, flange, "<mesh filename=\"package://piper/meshes/l6.stl\"/>"), yaml_,
               {"package://", "relative to the URDF"});
}


// Hostile robot files: every example the robot loader used to accept or crash on.
TEST_F(RobotLoaderTest, NonPhysicalUrdfGeometryIsRefused) {
  const std::string box = "<box size=\"0.25 0.06 0.07\"/>";
  for (const char* size : {"0 0.06 0.07", "-0.25 0.06 0.07", "1e9 0.06 0.07"})
    expect_error(replace(urdf_, box, std::string("<box size=\"") + size + "\"/>"), yaml_,
                 {"scout_mini_piper.urdf", "link 'link2' collision[0]", "box size x must be finite, > 0 and at most 5 m"});
  // urdfdom cannot parse "nan", logs it, drops the collision element and returns a model; the
  // loader refuses the file with urdfdom's reason.
  expect_error(replace(urdf_, box, "<box size=\"nan 0.06 0.07\"/>"), yaml_,
               {"scout_mini_piper.urdf", "not a valid URDF", "[nan]", "link2"});
  // A small shape placed 1e9 m away overflowed an int in the planner's distance grid.
  expect_error(replace(urdf_, "<origin xyz=\"0.1425 0.0 0.0\"", "<origin xyz=\"1e9 0.0 0.0\""), yaml_,
               {"link 'link2' collision[0]", "origin is 1e+09 m from its parent (limit 5 m)"});
  expect_error(replace(urdf_, "<cylinder radius=\"0.035\" length=\"0.02\"/>",
                       "<cylinder radius=\"0.035\" length=\"0\"/>"),
               yaml_, {"link6", "cylinder length"});
}

TEST_F(RobotLoaderTest, ZeroAxisAndAbsurdJointLimitsAreRefused) {
  const std::string joint2_axis =
      "<child link=\"link2\"/><origin xyz=\"0.0 0.0 0.0\" rpy=\"1.5707963267948966 -0.13578661580515894 "
      "-3.141592653589793\"/><axis xyz=\"0 0 1\"/>";
  std::string zero_axis = joint2_axis;
  zero_axis.replace(zero_axis.find("0 0 1"), 5, "0 0 0");
  expect_error(replace(urdf_, joint2_axis, zero_axis), yaml_, {"joint 'joint2'", "axis must be a finite non-zero vector"});
  // Joint limits of +-1e6 rad never finished building the planner's tables.
  expect_error(replace(urdf_, "lower=\"0.0\" upper=\"3.14\"", "lower=\"-1e6\" upper=\"1e6\""), yaml_,
               {"joint 'joint2'", "limits must be within +-6.28319 rad"});
}

TEST_F(RobotLoaderTest, BaseParametersOutsideTheirRangesAreRefused) {
  // wheel_radius_m: 1e308 planned "successfully" with NaN times; 1e-300 m turning radius aborted OMPL.
  expect_error(urdf_, replace(yaml_, "wheel_radius_m: 0.0875", "wheel_radius_m: 1e308"),
               {"robot.yaml", "base.wheel_radius_m", "must be within [0.001, 2]"});
  expect_error(urdf_, replace(yaml_, "min_turning_radius_m: 0.4", "min_turning_radius_m: 1e-300"),
               {"robot.yaml", "base.min_turning_radius_m", "must be within [0.001, 100]"});
  expect_error(urdf_, replace(yaml_, "[3.0, 3.0, 3.0, 4.0, 4.0, 4.0]", "[3.0, 3.0, 3.0, 4.0, 4.0, 1e300]"),
               {"joint_acceleration_max_radps2[5]", "must be within"});
  expect_error(urdf_, replace(yaml_, "track_width_m: 0.4165", "track_width_m: 0.4165\n  track_width_m: 9"),
               {"robot.yaml", "base.track_width_m", "appears twice"});
}

TEST_F(RobotLoaderTest, UrdfdomsReasonIsPassedOn) {
  // urdfdom logs why it refuses a file through console_bridge; the error carries it.
  try {
    load(replace(urdf_, "<parent link=\"link1\"/><child link=\"link2\"/>",
                 "<parent link=\"no_such_link\"/><child link=\"link2\"/>"),
         yaml_);
    FAIL();
  } catch (const LoadError& e) {
    EXPECT_NE(e.reason().find("not a valid URDF: "), std::string::npos) << e.what();
    EXPECT_NE(e.reason().find("no_such_link"), std::string::npos) << e.what();
  }
  expect_error(urdf_, replace(yaml_, "urdf: scout_mini_piper.urdf", "urdf: ."), {"'urdf'", "not a regular file"});
}

}  // namespace
}  // namespace porter
