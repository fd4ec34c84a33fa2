// Payload meshes load through assimp in every shipped format; payload YAML errors are precise;
// attaching a payload puts it on link 7 at the grasp transform.
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include "porter/core/kinematics.hpp"
#include "porter/core/load_error.hpp"
#include "porter/core/mesh_loader.hpp"
#include "porter/core/payload_loader.hpp"
#include "porter/core/robot_loader.hpp"
#include "robot_test_utils.hpp"

namespace porter {
namespace {

// Volume enclosed by a closed, outward-oriented mesh (divergence theorem).
double volume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles)
    v += m.vertices_m[t[0]].dot(m.vertices_m[t[1]].cross(m.vertices_m[t[2]])) / 6.0;
  return v;
}

const TriangleMesh& only_mesh(const Payload& p) {
  EXPECT_EQ(p.shapes.size(), 1u);
  return *std::get<MeshShape>(p.shapes.at(0).geometry).mesh;
}

TEST(PayloadTest, ShippedPayloadsAreClosedMeshesOfTheSpecifiedSize) {
  const Payload t = load_payload(test::payload_yaml("t_bar"));
  EXPECT_TRUE(only_mesh(t).closed);
  EXPECT_NEAR(volume(only_mesh(t)), 0.54 * 0.06 * 0.06 + 1.0 * 0.06 * 0.06, 1e-6);
  EXPECT_NEAR(only_mesh(t).bounds().sizes().x(), 0.6, 1e-6);
  EXPECT_NEAR(only_mesh(t).bounds().sizes().y(), 1.0, 1e-6);

  const Payload bar = load_payload(test::payload_yaml("long_bar"));
  EXPECT_TRUE(only_mesh(bar).closed);
  EXPECT_NEAR(volume(only_mesh(bar)), 1.4 * 0.10 * 0.06, 1e-6);

  const Payload arc = load_payload(test::payload_yaml("arc"));
  EXPECT_TRUE(only_mesh(arc).closed);
  // A 48-facet ring sector slightly under-fills the true quarter ring.
  EXPECT_NEAR(volume(only_mesh(arc)), M_PI / 2 * 0.5 * 0.06 * 0.06, 2e-5);
}

TEST(PayloadTest, DaeMeshesLoadThroughAssimp) {
  test::ScratchDir dir("payload_dae");
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(test::source_dir() + "/config/payloads/meshes/long_bar.obj", 0);
  ASSERT_NE(scene, nullptr);
  Assimp::Exporter exporter;
  ASSERT_EQ(exporter.Export(scene, "collada", dir.path("bar.dae")), AI_SUCCESS);
  const MeshPtr m = load_mesh(dir.path("bar.dae"), Eigen::Vector3d(2, 1, 1));
  EXPECT_TRUE(m->closed);
  EXPECT_NEAR(m->bounds().sizes().x(), 2.8, 1e-5);
  EXPECT_NEAR(volume(*m), 2 * 1.4 * 0.10 * 0.06, 1e-6);
}

TEST(PayloadTest, MeshLoaderErrors) {
  test::ScratchDir dir("payload_mesh");
  EXPECT_THROW(load_mesh(dir.path("none.stl")), LoadError);
  const std::string garbage = dir.file("bad.obj", "v 0 0 0\nv 1 0 0\n");  // no faces
  try {
    load_mesh(garbage);
    FAIL();
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj"), std::string::npos) << e.what();
  }
  EXPECT_THROW(load_mesh(test::source_dir() + "/config/payloads/meshes/t_bar.stl", Eigen::Vector3d(1, 0, 1)),
               LoadError);
  // An open mesh loads but says so.
  const std::string open = dir.file("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_FALSE(load_mesh(open)->closed);
}

void expect_payload_error(const test::ScratchDir& dir, const std::string& yaml, const std::string& fragment) {
  try {
    load_payload(dir.file("p.yaml", yaml));
    ADD_FAILURE() << "expected an error containing " << fragment;
  } catch (const LoadError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("p.yaml"), std::string::npos) << e.what();
  }
}

TEST(PayloadTest, YamlErrorsNameTheKey) {
  test::ScratchDir dir("payload_yaml");
  const std::string grasp = "grasp: {xyz: [0, 0, 0], rpy: [0, 0, 0]}\n";
  expect_payload_error(dir, "name: x\n" + grasp, "exactly one of 'mesh' and 'shapes'");
  expect_payload_error(dir, "name: x\nmesh: {file: a.stl}\nshapes: []\n" + grasp, "exactly one");
  expect_payload_error(dir, "name: x\nmesh: {file: missing.stl}\n" + grasp, "mesh.file");
  expect_payload_error(dir, "name: x\nshapes: [{box: {size: [1, -1, 1]}}]\n" + grasp, "shapes[0].box.size");
  expect_payload_error(dir, "name: x\nshapes: [{cone: {radius: 1}}]\n" + grasp, "unknown shape 'cone'");
  expect_payload_error(dir, "name: x\nshapes: [{sphere: {radius: 0.1}}]\n", "'grasp'");
  expect_payload_error(dir, "name: x\nshapes: [{sphere: {radius: 0.1}}]\ngrasp: {xyz: [0, 0]}\n", "grasp.xyz");
  expect_payload_error(dir, "name: x\nshapes: [{sphere: {radius: 0.1}}]\ncolour: red\n" + grasp, "colour");
}

// A 20 m sphere took the planner to 6.6 GB; payload size is now bounded like a link's.
TEST(PayloadTest, HostilePayloadsAreRefused) {
  test::ScratchDir dir("payload_hostile");
  const std::string grasp = "grasp: {xyz: [0, 0, 0], rpy: [0, 0, 0]}\n";
  expect_payload_error(dir, "name: x\nshapes: [{sphere: {radius: 20}}]\n" + grasp, "shapes[0]': reaches 20");
  expect_payload_error(dir, "name: x\nshapes: [{box: {size: [1e9, 1, 1]}}]\n" + grasp, "limit 5");
  expect_payload_error(dir, "name: x\nshapes: [{sphere: {radius: 0.1}}]\ngrasp: {xyz: [6, 0, 0]}\n", "grasp offset");
  expect_payload_error(dir, "name: x\nshapes: [{sphere: {radius: .nan}}]\n" + grasp, "expected a number");
  expect_payload_error(dir, "name: x\nname: y\nshapes: [{sphere: {radius: 0.1}}]\n" + grasp, "appears twice");
  // The shipped T-bar mesh scaled by 100 reaches beyond the limit.
  const std::string mesh = test::source_dir() + "/config/payloads/meshes/t_bar.stl";
  expect_payload_error(dir, "name: x\nmesh: {file: " + mesh + ", scale: 100}\n" + grasp, "key 'mesh'");
  EXPECT_NO_THROW(load_payload(dir.file("p.yaml", "name: x\nshapes: [{sphere: {radius: 2}}]\n" + grasp)));
}

TEST(PayloadTest, PrimitivePayloadAttachesAtTheGrasp) {
  test::ScratchDir dir("payload_attach");
  const Payload p = load_payload(dir.file(
      "ball.yaml", "name: ball\nshapes:\n  - sphere: {radius: 0.1, pose: {xyz: [0.2, 0, 0]}}\n"
                   "grasp: {xyz: [0, 0, 0.3], rpy: [0, 0, 1.5707963267948966]}\n"));
  const RobotModel bare = load_robot_model(test::robot_yaml());
  const RobotModel m = attach_payload(bare, p);
  EXPECT_EQ(m.payload_name, "ball");
  ASSERT_EQ(m.links[7].shapes.size(), bare.links[7].shapes.size() + 1);
  // The sphere centre: P's x axis is EE's y axis after the 90 degree yaw.
  const Eigen::Vector3d c = m.links[7].shapes.back().T_parent_shape.translation();
  EXPECT_NEAR((c - Eigen::Vector3d(0, 0.2, 0.3)).norm(), 0.0, 1e-12);
  EXPECT_GT(m.links[7].bounding_radius_m, bare.links[7].bounding_radius_m);
  // Other links are untouched.
  EXPECT_EQ(m.links[3].shapes.size(), bare.links[3].shapes.size());
}

TEST(PayloadTest, TBarStemPointsAlongTheApproachAxis) {
  const RobotModel m = attach_payload(load_robot_model(test::robot_yaml()), load_payload(test::payload_yaml("t_bar")));
  const Eigen::AlignedBox3d b = m.links[7].bounds;  // EE frame: gripper + T
  EXPECT_NEAR(b.max().z(), 0.55, 1e-6);            // stem end 5 cm inside the grasp, 0.6 m long
  EXPECT_NEAR(b.sizes().x(), 1.0, 1e-6);           // crossbar along EE x
}

}  // namespace
}  // namespace porter
