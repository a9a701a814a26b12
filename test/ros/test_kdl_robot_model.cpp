// KdlRobotModel (KDL through kdl_parser) against an independent forward kinematics written
// here from the URDF's own parse (urdf::Model: each joint's origin and axis composed with
// Eigen), on the demo arm and on a chain with a prismatic joint; and its lever-arm bounds
// (reach) against the distances sampled over random joint positions within the limits.
// No master.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <urdf/model.h>

#include "workspace_proximity/ros/kdl_robot_model.hpp"

namespace wp = workspace_proximity;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A prismatic joint between two revolute ones, with offsets along every axis, and a link
// fixed below the last joint.
const char* const kSlideArm = R"(<?xml version="1.0"?>
<robot name="slide_arm">
  <link name="base"/>
  <link name="a"/> <link name="b"/> <link name="c"/> <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.1 0.2 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/>
    <origin xyz="0.5 0 0" rpy="0 0.4 0"/><axis xyz="1 0 0"/>
    <limit lower="-0.2" upper="0.4" effort="1" velocity="1"/></joint>
  <joint name="j3" type="continuous"><parent link="b"/><child link="c"/>
    <origin xyz="0 0.3 -0.1" rpy="0 0 0"/><axis xyz="0 0.6 0.8"/></joint>
  <joint name="fixed_tip" type="fixed"><parent link="c"/><child link="tip"/>
    <origin xyz="0.25 0 0.05" rpy="0.3 0 0"/></joint>
</robot>)";

Eigen::Isometry3d toEigen(const urdf::Pose& p) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  double x, y, z, w;
  p.rotation.getQuaternion(x, y, z, w);
  out.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  return out;
}

// Pose of `link` in the root frame for joint positions by name: the URDF's rule, child =
// parent * origin * motion(axis, q).
Eigen::Isometry3d urdfPose(const urdf::Model& m, const std::string& link,
                           const std::map<std::string, double>& q) {
  const urdf::LinkConstSharedPtr l = m.getLink(link);
  if (!l->parent_joint) return Eigen::Isometry3d::Identity();
  const urdf::Joint& j = *l->parent_joint;
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d axis = Eigen::Vector3d(j.axis.x, j.axis.y, j.axis.z).normalized();
  const auto it = q.find(j.name);
  const double v = it == q.end() ? 0.0 : it->second;
  if (j.type == urdf::Joint::REVOLUTE || j.type == urdf::Joint::CONTINUOUS) {
    motion.linear() = Eigen::AngleAxisd(v, axis).toRotationMatrix();
  } else if (j.type == urdf::Joint::PRISMATIC) {
    motion.translation() = axis * v;
  }
  return urdfPose(m, j.parent_link_name, q) * toEigen(j.parent_to_joint_origin_transform) * motion;
}

void checkModel(const std::string& xml, int expected_joints, int expected_links) {
  urdf::Model urdf;
  ASSERT_TRUE(urdf.initString(xml));
  const wp::KdlRobotModel model(xml);
  EXPECT_EQ(model.root(), urdf.getRoot()->name);
  ASSERT_EQ(static_cast<int>(model.joints().size()), expected_joints);
  ASSERT_EQ(static_cast<int>(model.links().size()), expected_links);
  for (const wp::KinematicJoint& j : model.joints()) {
    const urdf::JointConstSharedPtr uj = urdf.getJoint(j.name);
    ASSERT_TRUE(uj);
    if (j.limited) {
      EXPECT_EQ(j.lower, uj->limits->lower);
      EXPECT_EQ(j.upper, uj->limits->upper);
    } else {
      EXPECT_EQ(uj->type, urdf::Joint::CONTINUOUS);
    }
  }
  std::mt19937 rng(11);
  std::vector<double> q(model.joints().size());
  std::vector<Eigen::Isometry3d> poses(model.links().size());
  for (int trial = 0; trial < 500; ++trial) {
    std::map<std::string, double> by_name;
    for (std::size_t k = 0; k < q.size(); ++k) {
      const wp::KinematicJoint& j = model.joints()[k];
      const double lo = j.limited ? j.lower : -M_PI, hi = j.limited ? j.upper : M_PI;
      q[k] = std::uniform_real_distribution<double>(lo, hi)(rng);
      by_name[j.name] = q[k];
    }
    model.forward(q.data(), poses.data());
    for (std::size_t l = 0; l < poses.size(); ++l) {
      const wp::KinematicLink& link = model.links()[l];
      const Eigen::Isometry3d truth = urdfPose(urdf, link.name, by_name);
      ASSERT_LT((poses[l].translation() - truth.translation()).norm(), 1e-9) << link.name;
      ASSERT_LT((poses[l].linear() - truth.linear()).norm(), 1e-9) << link.name;
      // Reach bounds: from the root's origin, and from each chain joint's axis point (the
      // origin of that joint's child link, which its motion leaves in place).
      ASSERT_LE(truth.translation().norm(), link.root_reach + 1e-9) << link.name;
      ASSERT_EQ(link.chain.size(), link.reach.size());
      for (std::size_t k = 0; k < link.chain.size(); ++k) {
        const std::string& joint = model.joints()[static_cast<std::size_t>(link.chain[k])].name;
        const Eigen::Isometry3d axis_point = urdfPose(urdf, urdf.getJoint(joint)->child_link_name, by_name);
        ASSERT_LE((truth.translation() - axis_point.translation()).norm(), link.reach[k] + 1e-9)
            << link.name << " from " << joint;
      }
    }
  }
}

}  // namespace

TEST(KdlRobotModel, DemoArmMatchesTheUrdf) {
  const std::string xml = readFile(WP_SOURCE_DIR "/config/demo_arm.urdf");
  ASSERT_FALSE(xml.empty());
  // shoulder_pan, shoulder_lift, elbow; every link below them (tool and tool_tip are fixed to
  // the forearm, so moved too); base_link is not listed.
  checkModel(xml, 3, 5);
}

TEST(KdlRobotModel, PrismaticAndContinuousJointsMatchTheUrdf) {
  checkModel(kSlideArm, 3, 4);
  const wp::KdlRobotModel model(kSlideArm);
  EXPECT_EQ(model.joints()[static_cast<std::size_t>(model.jointIndex("j2"))].type, wp::JointType::kPrismatic);
  EXPECT_EQ(model.joints()[static_cast<std::size_t>(model.jointIndex("j3"))].type, wp::JointType::kContinuous);
  const wp::KinematicLink& tip = model.links()[static_cast<std::size_t>(model.linkIndex("tip"))];
  EXPECT_EQ(tip.chain.size(), 3u);
  EXPECT_EQ(model.linkIndex("base"), -1);
}

TEST(KdlRobotModel, FixedOnlyRobotHasNoMovedLinks) {
  const wp::KdlRobotModel model(readFile(WP_SOURCE_DIR "/test/ros/fixtures/test_robot.urdf"));
  EXPECT_TRUE(model.joints().empty());
  EXPECT_TRUE(model.links().empty());
}

TEST(KdlRobotModel, RefusesWhatDoesNotParse) {
  EXPECT_THROW(wp::KdlRobotModel("<robot"), std::runtime_error);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
