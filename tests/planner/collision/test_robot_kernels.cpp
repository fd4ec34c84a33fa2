#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <tuple>

#include "collision_test_utils.hpp"
#include "porter/core/kinematics.hpp"
#include "porter/planner/collision/link_distance.hpp"
#include "porter/planner/collision/robot_kernels.hpp"

namespace porter::planner {
namespace {

using Key = std::tuple<int, int, int>;

/// A random point inside one of the link's shapes (link frame), by rejection.
bool random_point_in_link(const Link& link, std::mt19937_64& rng, Eigen::Vector3d* p) {
  if (link.shapes.empty()) return false;
  for (int tries = 0; tries < 1000; ++tries) {
    const auto& s =
        link.shapes[static_cast<std::size_t>(test::uniform(rng, 0, static_cast<double>(link.shapes.size())))];
    const Eigen::AlignedBox3d b = shape_bounds(s);
    const Eigen::Vector3d q(test::uniform(rng, b.min().x(), b.max().x()), test::uniform(rng, b.min().y(), b.max().y()),
                            test::uniform(rng, b.min().z(), b.max().z()));
    if (shape_contains(s, q)) {
      *p = q;
      return true;
    }
  }
  return false;
}

class RobotKernelsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = new RobotModel(test::shipped_robot_with("t_bar"));
    kernels_ = new RobotKernels(*model_, RobotKernelSettings{});
  }
  static void TearDownTestSuite() {
    delete kernels_;
    delete model_;
  }
  static RobotModel* model_;
  static RobotKernels* kernels_;
};
RobotModel* RobotKernelsTest::model_ = nullptr;
RobotKernels* RobotKernelsTest::kernels_ = nullptr;

TEST_F(RobotKernelsTest, CountsAddUpAndGrowLinearly) {
  int sum = 0;
  for (int j = 0; j < kNumLinks; ++j) {
    EXPECT_GE(kernels_->num_samples(j), 1);
    EXPECT_LE(kernels_->sample_error_m(j), 0.1 * 0.05 + 1e-12) << j;
    sum += kernels_->num_samples(j);
  }
  EXPECT_EQ(kernels_->kernel_count(), sum);
  EXPECT_EQ(kernels_->num_samples(kEndEffectorLink), 1);
  EXPECT_GT(kernels_->bytes(), 0u);
  // Halving the quantization error about doubles every N_j: the total doubles, not 2^7 times.
  RobotKernelSettings fine;
  fine.max_sample_error_m = 0.0025;
  const RobotKernels twice(*model_, fine);
  EXPECT_LT(twice.kernel_count(), 2 * kernels_->kernel_count() + 16);
  EXPECT_GT(twice.kernel_count(), 2 * kernels_->kernel_count() - 16);
}

TEST_F(RobotKernelsTest, BaseReachIsTheFarthestColumnOfAnyYaw) {
  int farthest = 0;
  for (int k = 0; k < kernels_->num_samples(0); ++k)
    for (const auto& d : kernels_->base_offsets(k)) {
      ASSERT_LE(d.x() * d.x() + d.y() * d.y(), kernels_->base_reach2()) << "yaw sample " << k;
      farthest = std::max(farthest, d.x() * d.x() + d.y() * d.y());
    }
  EXPECT_EQ(farthest, kernels_->base_reach2());
  // The Scout Mini's 0.61 x 0.42 m body (wheels beside it) at 5 cm: about 8-10 voxels.
  EXPECT_GT(kernels_->base_reach2(), 7 * 7);
  EXPECT_LT(kernels_->base_reach2(), 11 * 11);
}

TEST_F(RobotKernelsTest, BaseOffsetsHoldEveryVoxelTheBaseMeetsWithinItsBin) {
  const double h = kernels_->resolution_m();
  std::mt19937_64 rng(21);
  for (int trial = 0; trial < 300; ++trial) {
    const double fx = test::uniform(rng, 0, 1), fy = test::uniform(rng, 0, 1);
    const double yaw = test::uniform(rng, -M_PI, M_PI);
    const int k = kernels_->base_sample(yaw);
    std::set<Key> offsets;
    for (const auto& d : kernels_->base_offsets(k)) offsets.insert({d.x(), d.y(), d.z()});
    const Eigen::Isometry3d T =
        Eigen::Translation3d(fx * h, fy * h, 0.0) * Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ());
    for (const auto& s : model_->links[0].shapes) {
      CollisionShape sw = s;
      sw.T_parent_shape = T * s.T_parent_shape;
      const Eigen::AlignedBox3d b = shape_bounds(sw);
      for (int z = 0; z <= static_cast<int>(b.max().z() / h); ++z)
        for (int y = static_cast<int>(std::floor(b.min().y() / h)) - 1;
             y <= static_cast<int>(std::floor(b.max().y() / h)) + 1; ++y)
          for (int x = static_cast<int>(std::floor(b.min().x() / h)) - 1;
               x <= static_cast<int>(std::floor(b.max().x() / h)) + 1; ++x) {
            const Eigen::AlignedBox3d v(h * Eigen::Vector3d(x, y, z), h * Eigen::Vector3d(x + 1, y + 1, z + 1));
            if (shape_intersects_aabb(sw, v)) {
              ASSERT_TRUE(offsets.count({x, y, z})) << x << " " << y << " " << z << " yaw " << yaw;
            }
          }
    }
  }
}

TEST_F(RobotKernelsTest, NearestLatticePointOfAnyLinkPointIsInTheSelectedKernel) {
  const double h = kernels_->lattice_spacing_m();
  EXPECT_NEAR(h, kernels_->resolution_m() / RobotKernelSettings{}.lattice_subdivision, 1e-15);
  std::mt19937_64 rng(22);
  for (int link = 1; link < kNumLinks; ++link) {
    const Link& L = model_->links[static_cast<std::size_t>(link)];
    for (int trial = 0; trial < 150; ++trial) {
      int sample = 0;
      Eigen::Isometry3d T_J_L = Eigen::Isometry3d::Identity();
      if (link < kEndEffectorLink) {
        const ArmJoint& joint = model_->joints[static_cast<std::size_t>(link - 1)];
        const double q = test::uniform(rng, joint.lower_rad, joint.upper_rad);
        sample = kernels_->joint_sample(link, q);
        ASSERT_GE(sample, 0);
        ASSERT_LE(std::abs(kernels_->joint_sample_value(link, sample) - q),
                  0.5 * (joint.upper_rad - joint.lower_rad) / (kernels_->num_samples(link) - 1) + 1e-12);
        T_J_L = Eigen::AngleAxisd(q, joint.axis.normalized());
      }
      std::set<Key> members;
      for (const auto& p : kernels_->link_pool(link).points(sample))
        members.insert({static_cast<int>(std::lround(p.x() / h)), static_cast<int>(std::lround(p.y() / h)),
                        static_cast<int>(std::lround(p.z() / h))});
      for (int i = 0; i < 40; ++i) {
        Eigen::Vector3d x;
        ASSERT_TRUE(random_point_in_link(L, rng, &x));
        const Eigen::Vector3d xj = T_J_L * x / h;
        ASSERT_TRUE(members.count({static_cast<int>(std::lround(xj.x())), static_cast<int>(std::lround(xj.y())),
                                   static_cast<int>(std::lround(xj.z()))}))
            << "link " << link << " point " << x.transpose();
      }
    }
  }
}

TEST_F(RobotKernelsTest, KernelPointsLieWithinTheirRadiusOfTheSampledGeometry) {
  for (int link = 1; link < kNumLinks; ++link) {
    const LinkDistance d(model_->links[static_cast<std::size_t>(link)].shapes);
    for (int sample : {0, kernels_->num_samples(link) / 2, kernels_->num_samples(link) - 1}) {
      Eigen::Isometry3d T_L_J = Eigen::Isometry3d::Identity();
      if (link < kEndEffectorLink)
        T_L_J = Eigen::AngleAxisd(-kernels_->joint_sample_value(link, sample),
                                  model_->joints[static_cast<std::size_t>(link - 1)].axis.normalized());
      const auto pts = kernels_->link_pool(link).points(sample);
      EXPECT_FALSE(pts.empty());
      for (const auto& p : pts)
        EXPECT_LE(d.signed_distance(T_L_J * p.cast<double>()), kernels_->kernel_radius_m(link) + 1e-6);
    }
  }
}

TEST_F(RobotKernelsTest, SamplesCoverTheLimitsAndNothingBeyond) {
  for (int j = 1; j <= kNumArmJoints; ++j) {
    const ArmJoint& joint = model_->joints[static_cast<std::size_t>(j - 1)];
    const double step = (joint.upper_rad - joint.lower_rad) / (kernels_->num_samples(j) - 1);
    EXPECT_EQ(kernels_->joint_sample(j, joint.lower_rad), 0);
    EXPECT_EQ(kernels_->joint_sample(j, joint.upper_rad), kernels_->num_samples(j) - 1);
    EXPECT_EQ(kernels_->joint_sample(j, joint.lower_rad - 0.49 * step), 0);
    EXPECT_EQ(kernels_->joint_sample(j, joint.lower_rad - 0.51 * step), -1);
    EXPECT_EQ(kernels_->joint_sample(j, joint.upper_rad + 0.51 * step), -1);
    EXPECT_EQ(kernels_->joint_sample(j, std::nan("")), -1);
  }
  for (double yaw : {-M_PI, -1.0, 0.0, 2.0, M_PI, 7.0, -20.0}) {
    const int k = kernels_->base_sample(yaw);
    const double d = std::remainder(yaw - kernels_->base_sample_yaw(k), 2 * M_PI);
    EXPECT_LE(std::abs(d), M_PI / kernels_->num_samples(0) + 1e-12) << yaw;
  }
  // The inline fast path agrees with the general reduction, across the wrap and far from it.
  const int n = kernels_->num_samples(0);
  for (int i = -4 * n; i <= 4 * n; ++i)
    for (double frac : {-0.5, -0.4999, 0.0, 0.4999, 0.5}) {
      const double yaw = -M_PI + (i + frac) * 2 * M_PI / n;
      EXPECT_EQ(kernels_->base_sample(yaw), kernels_->base_sample_wrapped(yaw)) << yaw;
    }
  EXPECT_EQ(kernels_->base_sample(std::nan("")), 0);
  EXPECT_EQ(kernels_->base_sample(INFINITY), 0);
}

// The map padding is max_extent_voxels(): no kernel point or offset may reach farther from the
// base origin, whatever the configuration, also for coarse sampling settings.
TEST(RobotKernels, RefusesKernelRadiiOfAVoxelOrMore) {
  // The neighbourhood test of a kernel point only looks one voxel around it (robot_kernels.hpp).
  const RobotModel model = test::shipped_robot();
  RobotKernelSettings s;
  s.lattice_subdivision = 1;
  s.max_sample_error_m = 0.01;  // d_j = 4.3 + 1 cm > 5 cm
  EXPECT_THROW(RobotKernels(model, s), std::invalid_argument);
  s.lattice_subdivision = 0;
  EXPECT_THROW(RobotKernels(model, s), std::invalid_argument);
}

TEST(RobotKernels, EverythingStaysWithinTheStatedExtent) {
  const RobotModel model = test::shipped_robot_with("arc");
  RobotKernelSettings coarse;
  coarse.base_yaw_samples = 8;
  coarse.max_sample_error_m = 0.006;  // with a lattice of one voxel: d_j = 4.3 + 0.6 cm, just under h
  coarse.lattice_subdivision = 1;
  for (const RobotKernelSettings& settings : {RobotKernelSettings{}, coarse}) {
    const RobotKernels kernels(model, settings);
    const double h = kernels.resolution_m();
    const double limit = kernels.max_extent_voxels() * h;
    for (int k = 0; k < kernels.num_samples(0); ++k)
      for (const auto& d : kernels.base_offsets(k)) ASSERT_LE(d.cwiseAbs().maxCoeff() + 1, kernels.max_extent_voxels());
    std::mt19937_64 rng(23);
    for (int i = 0; i < 200; ++i) {
      RobotConfiguration c;
      c.q_rad = test::random_joints(model, rng);
      KinematicsWorkspace ws;
      forward_kinematics(model, c, ws);
      for (int link = 1; link < kNumLinks; ++link) {
        const int sample = link == kEndEffectorLink ? 0 : kernels.joint_sample(link, c.q_rad[link - 1]);
        for (const auto& p : kernels.link_pool(link).points(sample))
          ASSERT_LE((ws.T_W_J[static_cast<std::size_t>(link)] * p.cast<double>()).cwiseAbs().maxCoeff(), limit - h);
      }
    }
  }
}

}  // namespace
}  // namespace porter::planner
