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
               {"base.wheel_radius_m", "positive"});
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

}  // namespace
}  // namespace porter
