// Posing robot bodies from the joints without ROS (JointPosing): which bodies it claims, joint
// states read by name (unknown names skipped, a velocity array that does not match the names
// "not measured", stamp 0 the arrival), planned trajectories refused whole with the reason and
// counted, and each cycle's poses against the turntable's forward kinematics worked out by hand.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "workspace_proximity/rules/joint_posing.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kNow = 1000 * kSecond;

// A turntable: joint "turn" about z at the root's origin moves link "arm".
class Turntable : public wp::KinematicModel {
 public:
  Turntable() {
    root_ = "base";
    joints_ = {{"turn", wp::JointType::kRevolute, true, -3.0, 3.0}};
    links_ = {{"arm", {0}, {0.0}, 0.0}};
  }
  void forward(const double* q, Eigen::Isometry3d* poses) const override {
    poses[0] = Eigen::Isometry3d(Eigen::AngleAxisd(q[0], Eigen::Vector3d::UnitZ()));
  }
};

wp::RobotBodySpec onFrame(const std::string& name, const std::string& frame, double x) {
  wp::RobotBodySpec s = wp_test::robotBox(name, {0.1, 0.1, 0.1}, {x, 0.0, 0.0});
  s.frame = frame;
  return s;
}

struct Fixture {
  // Robot bodies: 0 on the root (tf), 1 on the arm 1 m out (joints), 2 on a camera (tf).
  Fixture()
      : monitor(wp_test::marginFreeParams(2.0),
                {onFrame("plate", "base", 0.0), onFrame("tip", "arm", 1.0),
                 onFrame("cam", "camera", 0.0)},
                {"/boxes"}, false, nullptr),
        posing(&monitor, std::make_shared<Turntable>()) {}
  Eigen::Vector3d tip() const {
    return monitor.world().motion(monitor.robot().handle(1)).position;
  }
  wp::Monitor monitor;
  wp::JointPosing posing;
  wp::BodyMotion base;  // the root at the origin, standing still
};

}  // namespace

TEST(JointPosing, ClaimsTheBodiesOnLinksTheJointsMove) {
  Fixture f;
  EXPECT_EQ(f.posing.claimed(), std::vector<int>{1});
}

TEST(JointPosing, AMeasuredJointStatePosesTheBodyByForwardKinematics) {
  Fixture f;
  // "wrist" is not the model's: skipped. Stamp 0: the arrival, so the reading is fresh.
  f.posing.onJointState({"wrist", "turn"}, {9.0, M_PI / 2}, {0.0, 0.5}, 0, kNow);
  EXPECT_EQ(f.posing.counters().joint_states, 1u);
  const wp::JointPosingLog log = f.posing.update(kNow, &f.base, "", "");
  EXPECT_EQ(log.unknown, -1);
  EXPECT_EQ(log.refused, -1);
  EXPECT_FALSE(log.plan_dropped);
  ASSERT_TRUE(f.monitor.robot().present(1));
  EXPECT_FALSE(f.monitor.robot().stale(1)) << f.monitor.robot().why(1);
  // 1 m out along the arm turned by 90 degrees: (0, 1, 0), turning at 0.5 rad/s about z.
  EXPECT_LT((f.tip() - Eigen::Vector3d(0, 1, 0)).norm(), 1e-9);
  const wp::BodyMotion& m = f.monitor.world().motion(f.monitor.robot().handle(1));
  EXPECT_LT((m.angular_velocity - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-9);
  // The bodies on the root and the camera are tf's: untouched.
  EXPECT_FALSE(f.monitor.robot().present(0));
  EXPECT_FALSE(f.monitor.robot().present(2));
}

TEST(JointPosing, AVelocityArrayThatDoesNotMatchTheNamesIsNotMeasured) {
  Fixture f;
  // Two names, one velocity: not measured, and one reading gives no finite difference, so the
  // tip is posed where it is but stale.
  f.posing.onJointState({"wrist", "turn"}, {9.0, M_PI / 2}, {0.5}, kNow, kNow);
  f.posing.update(kNow, &f.base, "", "");
  ASSERT_TRUE(f.monitor.robot().present(1));
  EXPECT_TRUE(f.monitor.robot().stale(1));
  EXPECT_LT((f.tip() - Eigen::Vector3d(0, 1, 0)).norm(), 1e-9);
}

TEST(JointPosing, TheRootsStaleReasonMakesAMovingBodyStale) {
  Fixture f;
  f.posing.onJointState({"turn"}, {0.0}, {0.5}, kNow, kNow);
  f.posing.update(kNow, &f.base, "", "velocity not known yet");
  ASSERT_TRUE(f.monitor.robot().present(1));
  EXPECT_TRUE(f.monitor.robot().stale(1));
  EXPECT_EQ(f.monitor.robot().why(1), "velocity not known yet");
  EXPECT_LT((f.tip() - Eigen::Vector3d(1, 0, 0)).norm(), 1e-9);
}

TEST(JointPosing, WithoutTheRootOrAReadingTheBodiesAreUnknown) {
  Fixture f;
  // The root not posed: every claimed body unknown with the root's reason.
  f.posing.update(kNow, nullptr, "no transform 'world' -> 'base'", "");
  EXPECT_TRUE(f.monitor.robot().stale(1));
  EXPECT_EQ(f.monitor.robot().why(1), "root frame 'base' not posed: no transform 'world' -> 'base'");
  // The root posed but the joint never read: unknown with the predictor's reason, logged.
  const wp::JointPosingLog log = f.posing.update(kNow, &f.base, "", "");
  EXPECT_EQ(log.unknown, 0);
  EXPECT_TRUE(f.monitor.robot().stale(1));
  EXPECT_EQ(f.monitor.robot().why(1), f.posing.predictor().body(0).why);
  EXPECT_FALSE(f.monitor.robot().why(1).empty());
  // A reading older than the monitor's ~tf_timeout (0.5 s by default, the predictor's
  // state_timeout): unknown too. Stamp 0 would be such a reading, were it not the arrival.
  f.posing.onJointState({"turn"}, {0.0}, {0.0}, kNow - kSecond, kNow - kSecond);
  EXPECT_EQ(f.posing.update(kNow, &f.base, "", "").unknown, 0);
}

TEST(JointPosing, ABadTrajectoryIsRefusedWholeWithItsReasonAndCounted) {
  Fixture f;
  wp::PlannedTrajectory unknown_joint;
  unknown_joint.joint_names = {"wrist"};
  unknown_joint.times = {1.0};
  unknown_joint.positions = {{0.5}};
  EXPECT_EQ(f.posing.onTrajectory(unknown_joint, kNow),
            "joint 'wrist' is not a movable joint of the robot model");
  wp::PlannedTrajectory ragged;
  ragged.joint_names = {"turn"};
  ragged.times = {0.5, 1.0};
  ragged.positions = {{0.5}, {0.5, 1.0}};
  EXPECT_EQ(f.posing.onTrajectory(ragged, kNow), "a point's positions do not match its joint names");
  EXPECT_EQ(f.posing.counters().trajectories_ignored, 2u);
  EXPECT_EQ(f.posing.counters().last_trajectory_problem,
            "trajectory ignored: a point's positions do not match its joint names");
  EXPECT_FALSE(f.posing.predictor().hasPlan());
  wp::PlannedTrajectory good;
  good.joint_names = {"turn"};
  good.times = {1.0};
  good.positions = {{0.5}};
  EXPECT_EQ(f.posing.onTrajectory(good, kNow), "");
  EXPECT_EQ(f.posing.counters().trajectories, 1u);
  EXPECT_TRUE(f.posing.predictor().hasPlan());
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
