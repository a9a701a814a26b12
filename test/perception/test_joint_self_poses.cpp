// The self-filter's robot from the joints at a cloud's stamp (JointSelfPoses) against an
// analytic arm: one revolute joint about z turning a 1 m box, its true angle known at every
// instant. Joint readings arrive late (the cloud's stamp after the newest) or around the
// cloud's stamp; the self-filter built from the poses at the stamp must remove every point
// sampled densely on the box's true surface at the stamp (the oracle), and keep a point just
// outside padding + bound. The old path (the newest pose, grown by a global speed bound) is
// shown to leave some of the arm's points when the arm's tip is faster than that bound.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "workspace_proximity/perception/joint_self_poses.hpp"
#include "workspace_proximity/perception/self_filter.hpp"

namespace wp = workspace_proximity;
namespace pc = workspace_proximity::perception;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPadding = 0.02;  // m
const Eigen::Vector3d kHalf(0.5, 0.05, 0.05);  // the arm box, from its axis to 1 m along x

// One joint "swing" about z at the root's origin turning link "arm".
class SwingArm : public wp::KinematicModel {
 public:
  SwingArm() {
    root_ = "world";
    joints_ = {{"swing", wp::JointType::kRevolute, true, -3.0, 3.0}};
    links_ = {{"arm", {0}, {0.0}, 0.0}};  // the link's origin is on the axis
  }
  void forward(const double* q, Eigen::Isometry3d* poses) const override {
    poses[0] = Eigen::Isometry3d(Eigen::AngleAxisd(q[0], Eigen::Vector3d::UnitZ()));
  }
};

std::vector<wp::RobotBodySpec> robot() {
  wp::RobotBodySpec arm;
  arm.name = "arm_box";
  arm.frame = "arm";
  arm.shape = wp::Shape::box(kHalf);
  arm.offset = Eigen::Translation3d(0.5, 0.0, 0.0);
  wp::RobotBodySpec base;  // on the root: not the joints' (tf)
  base.name = "base";
  base.frame = "world";
  base.shape = wp::Shape::box(Eigen::Vector3d::Constant(0.1));
  return {arm, base};
}

wp::Stamp ms(double t) { return wp::nanoseconds(t * 1e-3); }

// The box's pose at joint angle q.
Eigen::Isometry3d boxPose(double q) {
  return Eigen::Isometry3d(Eigen::AngleAxisd(q, Eigen::Vector3d::UnitZ())) * Eigen::Translation3d(0.5, 0, 0);
}

// Points on the box's surface every 5 mm (and its edges), at joint angle q, fixed frame.
std::vector<Eigen::Vector3f> surface(double q) {
  std::vector<Eigen::Vector3f> out;
  const Eigen::Isometry3d pose = boxPose(q);
  const double step = 0.005;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = static_cast<int>(std::round(2 * kHalf[u] / step));
    const int nv = static_cast<int>(std::round(2 * kHalf[v] / step));
    for (int side = -1; side <= 1; side += 2) {
      for (int i = 0; i <= nu; ++i) {
        for (int j = 0; j <= nv; ++j) {
          Eigen::Vector3d p;
          p[axis] = side * kHalf[axis];
          p[u] = -kHalf[u] + 2 * kHalf[u] * i / nu;
          p[v] = -kHalf[v] + 2 * kHalf[v] * j / nv;
          out.push_back((pose * p).cast<float>());
        }
      }
    }
  }
  return out;
}

// How many of `points` the self-filter built from `link` does not remove.
int kept(const pc::SelfLink& link, const std::vector<Eigen::Vector3f>& points) {
  pc::SelfFilter filter(4);
  EXPECT_TRUE(filter.setLinks(&link, 1, kPadding, 0.0, 0.05));
  int n = 0;
  for (const Eigen::Vector3f& p : points) n += filter.classify(p) != pc::SelfVerdict::kSelf ? 1 : 0;
  return n;
}

// A point `beyond` m outside the grown posed box: from the middle of its +y face (in the
// box's frame), straight out.
Eigen::Vector3f justOutside(const pc::SelfLink& link, double beyond) {
  pc::SelfFilter filter(4);
  filter.setLinks(&link, 1, kPadding, 0.0, 0.05);
  const Eigen::Vector3d local(0.0, kHalf.y() + filter.growth(0) + beyond, 0.0);
  return (link.pose * local).cast<float>();
}

struct Fixture {
  pc::JointSelfPoses poses{std::make_shared<SwingArm>(), robot(), wp::JointPredictorParams()};
  std::vector<pc::SelfLink> links = std::vector<pc::SelfLink>(2);
  // One reading of the swing joint at t ms: angle, velocity (NaN: not measured).
  void read(double t, double q, double v) {
    poses.onJointState({"swing"}, {q}, std::isnan(v) ? std::vector<double>{} : std::vector<double>{v}, ms(t),
                       ms(t));
  }
};

// The arm at angular speed w from angle 0 at t = 0.
double turning(double w, double t_ms) { return w * t_ms * 1e-3; }

}  // namespace

TEST(JointSelfPoses, ClaimsOnlyBodiesOnJointDrivenLinks) {
  Fixture f;
  EXPECT_TRUE(f.poses.claims(0));
  EXPECT_FALSE(f.poses.claims(1));  // on the root: tf
  EXPECT_EQ(f.poses.claimedCount(), 1);
}

TEST(JointSelfPoses, LateReadingsPredictedToTheStampRemoveTheWholeTrueArm) {
  // Full speed: 3 rad/s, the tip at 3 m/s. Readings every 20 ms with their velocity; the cloud
  // is stamped 35 ms after the newest (the joint states are late).
  const double w = 3.0;
  Fixture f;
  for (double t = 0; t <= 100; t += 20) f.read(t, turning(w, t), w);
  const double stamp = 135;
  ASSERT_EQ(f.poses.poseAt(ms(stamp), Eigen::Isometry3d::Identity(), f.links.data()), 1);
  EXPECT_EQ(f.poses.why(0), "");
  const pc::SelfLink& link = f.links[0];
  // The bound: w x lever (0.5 to the centre + the box's bounding radius) over 35 ms.
  const double lever = 0.5 + kHalf.norm();
  EXPECT_NEAR(link.speed, w * lever, 1e-9);
  // For one joint it is linkSpeedBound of the box's twist (its centre 0.5 m from the axis).
  wp::BodyMotion twist;
  twist.linear_velocity = Eigen::Vector3d(0.0, w * 0.5, 0.0);
  twist.angular_velocity = Eigen::Vector3d(0.0, 0.0, w);
  EXPECT_NEAR(link.speed, pc::linkSpeedBound(twist, wp::Shape::box(kHalf)), 1e-9);
  EXPECT_NEAR(link.gap, 0.035, 1e-9);
  // At constant speed the prediction is the truth (the monitor's model: its velocity).
  EXPECT_TRUE(link.pose.isApprox(boxPose(turning(w, stamp)), 1e-9));
  EXPECT_EQ(kept(link, surface(turning(w, stamp))), 0);
  // Decelerated after the last reading (within the same speed): still inside.
  EXPECT_EQ(kept(link, surface(turning(w, 100) + 0.5 * w * 0.035)), 0);
  EXPECT_EQ(kept(link, surface(turning(w, 100))), 0);  // stopped right at the reading
  // A point just outside padding + bound is kept.
  pc::SelfFilter filter(4);
  ASSERT_TRUE(filter.setLinks(&link, 1, kPadding, 0.0, 0.05));
  EXPECT_NEAR(filter.growth(0), kPadding + w * lever * 0.035, 1e-9);
  EXPECT_NE(filter.classify(justOutside(link, 0.002)), pc::SelfVerdict::kSelf);
  EXPECT_EQ(filter.classify(justOutside(link, -0.002)), pc::SelfVerdict::kSelf);
}

TEST(JointSelfPoses, TheOldNewestPoseWithAGlobalSpeedBoundMissesTheArm) {
  // The same arm and readings. The old path: the link at its newest pose (tf's newest, here
  // the newest reading), grown by ~self_max_speed (2 m/s, the default) x the gap: the tip
  // moves at 3 m/s, so points near the tip are left as obstacles.
  const double w = 3.0;
  const double stamp = 135;
  pc::SelfLink old;
  old.shape = wp::Shape::box(kHalf);
  old.pose = boxPose(turning(w, 100));
  old.speed = 2.0;
  old.gap = 0.035;
  EXPECT_GT(kept(old, surface(turning(w, stamp))), 0);
  // Even a larger gap bound for the same speed bound would not be the issue: the speed is.
  Fixture f;
  for (double t = 0; t <= 100; t += 20) f.read(t, turning(w, t), w);
  ASSERT_EQ(f.poses.poseAt(ms(stamp), Eigen::Isometry3d::Identity(), f.links.data()), 1);
  EXPECT_EQ(kept(f.links[0], surface(turning(w, stamp))), 0);
}

TEST(JointSelfPoses, AStampBetweenReadingsIsInterpolated) {
  // Readings every 20 ms; clouds stamped between two of them (joint states that arrived after
  // the cloud). Constant speed: the interpolation is exact; stop-and-go within the readings'
  // speeds: inside padding + bound.
  const double w = 3.0;
  Fixture f;
  for (double t = 0; t <= 200; t += 20) f.read(t, turning(w, t), w);
  for (double stamp : {40.0, 47.0, 50.0, 59.0, 100.0, 193.0}) {
    ASSERT_EQ(f.poses.poseAt(ms(stamp), Eigen::Isometry3d::Identity(), f.links.data()), 1) << stamp;
    const pc::SelfLink& link = f.links[0];
    const double d = std::fmod(stamp, 20.0) * 1e-3, e = 0.02 - d;
    EXPECT_NEAR(link.gap, 2 * d * e / 0.02, 1e-9) << stamp;
    EXPECT_TRUE(link.pose.isApprox(boxPose(turning(w, stamp)), 1e-9)) << stamp;
    EXPECT_EQ(kept(link, surface(turning(w, stamp))), 0) << stamp;
    EXPECT_NE(kept(link, {justOutside(link, 0.002)}), 0) << stamp;
  }
  // Not at constant speed: any motion between the readings at most 3 rad/s is within w x gap
  // of the line. At 47 ms: it went at full speed then stopped (ahead of the line), or waited
  // then went (behind it).
  Fixture g;
  g.read(40, 0.0, w);
  g.read(60, 0.5 * w * 0.02, w);  // half the way in 20 ms: went 10 ms at 3 rad/s
  ASSERT_EQ(g.poses.poseAt(ms(47), Eigen::Isometry3d::Identity(), g.links.data()), 1);
  EXPECT_EQ(kept(g.links[0], surface(w * 0.007)), 0);                // went first (ahead)
  EXPECT_EQ(kept(g.links[0], surface(std::max(0.0, w * (0.007 - 0.010)))), 0);  // waited first
}

TEST(JointSelfPoses, FiniteDifferencesWhenNoVelocityIsMeasured) {
  const double w = 2.0;
  Fixture f;
  for (double t = 0; t <= 100; t += 20) f.read(t, turning(w, t), kNaN);
  ASSERT_EQ(f.poses.poseAt(ms(130), Eigen::Isometry3d::Identity(), f.links.data()), 1);
  EXPECT_NEAR(f.links[0].speed, w * (0.5 + kHalf.norm()), 1e-6);
  EXPECT_EQ(kept(f.links[0], surface(turning(w, 130))), 0);
}

TEST(JointSelfPoses, WhatCannotBePredictedIsNamed) {
  Fixture f;
  EXPECT_EQ(f.poses.poseAt(ms(10), Eigen::Isometry3d::Identity(), f.links.data()), 0);
  EXPECT_NE(f.poses.why(0).find("no joint state for joint 'swing'"), std::string::npos) << f.poses.why(0);
  // One reading without velocity: the motion is not known.
  f.read(0, 0.1, kNaN);
  EXPECT_EQ(f.poses.poseAt(ms(10), Eigen::Isometry3d::Identity(), f.links.data()), 0);
  EXPECT_NE(f.poses.why(0).find("velocity of joint 'swing' not known"), std::string::npos) << f.poses.why(0);
  // Older than the monitor's ~tf_timeout (0.5 s) at the stamp.
  f.read(20, 0.1, 0.0);
  EXPECT_EQ(f.poses.poseAt(ms(30), Eigen::Isometry3d::Identity(), f.links.data()), 1);
  EXPECT_EQ(f.poses.poseAt(ms(600), Eigen::Isometry3d::Identity(), f.links.data()), 0);
  EXPECT_NE(f.poses.why(0).find("joint state of 'swing' is 0.580 s older"), std::string::npos) << f.poses.why(0);
  // Before the oldest reading kept; and readings too far apart around the stamp.
  EXPECT_EQ(f.poses.poseAt(ms(-5), Eigen::Isometry3d::Identity(), f.links.data()), 0);
  EXPECT_NE(f.poses.why(0).find("joint 'swing': the frame's stamp is 0.005 s before the oldest joint state kept"), std::string::npos);
  f.read(800, 0.1, 0.0);
  EXPECT_EQ(f.poses.poseAt(ms(400), Eigen::Isometry3d::Identity(), f.links.data()), 0);
  EXPECT_NE(f.poses.why(0).find("had no state for 0.780 s"), std::string::npos) << f.poses.why(0);
  // A shape the self-filter refuses stays refused: a NaN gap.
  pc::SelfLink bad = f.links[0];
  bad.gap = kNaN;
  pc::SelfFilter filter(2);
  EXPECT_FALSE(filter.setLinks(&bad, 1, kPadding, 0.0, 0.05));
}

TEST(JointSelfPoses, APlannedTrajectoryIsFollowedAfterTheNewestReading) {
  // Readings say 0.5 rad/s, but the plan (as the monitor takes it) turns the arm to 1.0 rad in
  // 0.2 s from its start: the pose at the stamp is the plan's, the bound at least the speed
  // needed to get there from the reading.
  Fixture f;
  f.read(0, 0.0, 0.5);
  wp::PlannedTrajectory plan;
  plan.start = ms(0);
  plan.joint_names = {"swing"};
  plan.times = {0.0, 0.2};
  plan.positions = {{0.0}, {1.0}};
  ASSERT_EQ(f.poses.onTrajectory(plan, ms(0)), "");
  ASSERT_EQ(f.poses.poseAt(ms(40), Eigen::Isometry3d::Identity(), f.links.data()), 1);
  EXPECT_EQ(kept(f.links[0], surface(0.2)), 0);  // where the plan has it at 40 ms
  EXPECT_NEAR(f.links[0].speed, 5.0 * (0.5 + kHalf.norm()), 1e-6);
  EXPECT_EQ(kept(f.links[0], surface(0.0)), 0);  // and where the reading left it
}

TEST(JointSelfPoses, TheRootFrameCarriesTheArm) {
  const double w = 1.0;
  Fixture f;
  for (double t = 0; t <= 40; t += 20) f.read(t, turning(w, t), w);
  const Eigen::Isometry3d root = Eigen::Translation3d(1.0, 2.0, 0.5) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
  ASSERT_EQ(f.poses.poseAt(ms(40), root, f.links.data()), 1);
  EXPECT_TRUE(f.links[0].pose.isApprox(root * boxPose(turning(w, 40)), 1e-9));
}

namespace {

// Two joints about z: "shoulder" at the root's origin, "elbow" 1 m along the upper link; a
// 0.6 m box on the forearm from the elbow along its x.
class TwoJointArm : public wp::KinematicModel {
 public:
  TwoJointArm() {
    root_ = "world";
    joints_ = {{"shoulder", wp::JointType::kRevolute, true, -3.0, 3.0},
               {"elbow", wp::JointType::kRevolute, true, -3.0, 3.0}};
    links_ = {{"upper", {0}, {0.0}, 0.0}, {"fore", {0, 1}, {1.0, 0.0}, 1.0}};
  }
  void forward(const double* q, Eigen::Isometry3d* poses) const override {
    poses[0] = Eigen::Isometry3d(Eigen::AngleAxisd(q[0], Eigen::Vector3d::UnitZ()));
    poses[1] = poses[0] * Eigen::Translation3d(1.0, 0, 0) * Eigen::AngleAxisd(q[1], Eigen::Vector3d::UnitZ());
  }
};

const Eigen::Vector3d kFore(0.3, 0.05, 0.05);

// Points every 5 mm on the forearm box's surface at joint angles (a, b).
std::vector<Eigen::Vector3f> foreSurface(double a, double b) {
  const Eigen::Isometry3d pose = Eigen::Isometry3d(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())) *
                                 Eigen::Translation3d(1.0, 0, 0) * Eigen::AngleAxisd(b, Eigen::Vector3d::UnitZ()) *
                                 Eigen::Translation3d(0.3, 0, 0);
  std::vector<Eigen::Vector3f> out;
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const int nu = static_cast<int>(std::round(2 * kFore[u] / 0.005));
    const int nv = static_cast<int>(std::round(2 * kFore[v] / 0.005));
    for (int side = -1; side <= 1; side += 2) {
      for (int i = 0; i <= nu; ++i) {
        for (int j = 0; j <= nv; ++j) {
          Eigen::Vector3d p;
          p[axis] = side * kFore[axis];
          p[u] = -kFore[u] + 2 * kFore[u] * i / nu;
          p[v] = -kFore[v] + 2 * kFore[v] * j / nv;
          out.push_back((pose * p).cast<float>());
        }
      }
    }
  }
  return out;
}

}  // namespace

TEST(JointSelfPoses, AChainIsBoundByTheSumOfItsJointsLevers) {
  // Shoulder at 2 rad/s, elbow at -3 rad/s, readings every 20 ms, the stamp 30 ms after the
  // newest. Any motion that keeps each joint within its speed x gap of the prediction (the
  // nine extremes: each joint behind, on or ahead of it by s g) stays inside padding + bound.
  wp::RobotBodySpec fore;
  fore.name = "fore_box";
  fore.frame = "fore";
  fore.shape = wp::Shape::box(kFore);
  fore.offset = Eigen::Translation3d(0.3, 0.0, 0.0);
  pc::JointSelfPoses poses(std::make_shared<TwoJointArm>(), {fore}, wp::JointPredictorParams());
  const double w1 = 2.0, w2 = -3.0;
  for (double t = 0; t <= 100; t += 20) {
    poses.onJointState({"shoulder", "elbow"}, {w1 * t * 1e-3, w2 * t * 1e-3}, {w1, w2}, ms(t), ms(t));
  }
  std::vector<pc::SelfLink> links(1);
  ASSERT_EQ(poses.poseAt(ms(130), Eigen::Isometry3d::Identity(), links.data()), 1);
  const double tail = 0.3 + kFore.norm();
  EXPECT_NEAR(links[0].speed, std::abs(w1) * (1.0 + tail) + std::abs(w2) * tail, 1e-9);
  EXPECT_NEAR(links[0].gap, 0.03, 1e-9);
  const double g = 0.03;
  for (int i = -1; i <= 1; ++i) {
    for (int j = -1; j <= 1; ++j) {
      const double a = w1 * 0.13 + i * std::abs(w1) * g, b = w2 * 0.13 + j * std::abs(w2) * g;
      EXPECT_EQ(kept(links[0], foreSurface(a, b)), 0) << i << " " << j;
    }
  }
  EXPECT_NE(kept(links[0], {justOutside(links[0], 0.002)}), 0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
