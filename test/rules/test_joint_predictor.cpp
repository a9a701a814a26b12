// The joint-space predictor against closed-form kinematics: a planar arm written out by hand
// (the model), its true motion computed from the joints' analytic trajectories (constant
// velocity, stopped at a limit, a planned trajectory's straight lines), and every point of each
// body's box compared with the keyframed path the predictor hands to the core: never further
// apart than that segment's margin (the stated bound), exact at the keyframes. Finite
// differences, stale and missing readings, plan checks and the contradiction rule.

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "allocation_counter.hpp"  // test/shared
#include "workspace_proximity/rules/joint_predictor.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kNow = 100 * kSecond;

// Planar arm in the x-y plane: joint 0 turns about z at the origin, link "upper" of length
// l1 along its x; joint 1 turns about z at the end of upper, link "fore" of length l2; joint 2
// slides fore's child "slider" along fore's x, from 0 to 0.3 m.
class PlanarArm : public wp::KinematicModel {
 public:
  static constexpr double l1 = 1.0, l2 = 0.6;
  PlanarArm() {
    root_ = "base";
    joints_ = {{"shoulder", wp::JointType::kRevolute, true, -2.0, 2.0},
               {"elbow", wp::JointType::kRevolute, true, -1.0, 1.0},
               {"slide", wp::JointType::kPrismatic, true, 0.0, 0.3}};
    // Reach from each joint's axis point to the link origin, bounded by hand.
    links_ = {{"upper", {0}, {0.0}, 0.0},
              {"fore", {0, 1}, {l1, 0.0}, l1},
              {"slider", {0, 1, 2}, {l1 + l2 + 0.3, l2 + 0.3, 0.3}, l1 + l2 + 0.3}};
  }
  void forward(const double* q, Eigen::Isometry3d* poses) const override {
    poses[0] = Eigen::Isometry3d(Eigen::AngleAxisd(q[0], Eigen::Vector3d::UnitZ()));
    poses[1] = poses[0] * Eigen::Translation3d(l1, 0, 0) * Eigen::AngleAxisd(q[1], Eigen::Vector3d::UnitZ());
    poses[2] = poses[1] * Eigen::Translation3d(l2 + q[2], 0, 0);
  }
};

// A body: a box of half extents `half` at `offset` in its link.
struct TestBody {
  int link;
  Eigen::Isometry3d offset;
  Eigen::Vector3d half;
};

std::vector<Eigen::Vector3d> corners(const Eigen::Vector3d& half) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 8; ++i) {
    out.emplace_back((i & 1 ? 1 : -1) * half.x(), (i & 2 ? 1 : -1) * half.y(), (i & 4 ? 1 : -1) * half.z());
  }
  out.emplace_back(Eigen::Vector3d::Zero());
  return out;
}

// The path's pose at t and the margin of the segment in force.
Eigen::Isometry3d pathPose(const std::vector<wp::MotionSegment>& path, double t, double* margin) {
  std::size_t k = 0;
  while (k + 1 < path.size() && path[k + 1].start <= t) ++k;
  *margin = path[k].margin;
  return path[k].motion.poseAt(t - path[k].start);
}

struct Fixture {
  std::shared_ptr<PlanarArm> arm = std::make_shared<PlanarArm>();
  std::vector<TestBody> bodies;
  wp::JointPredictor predictor;
  explicit Fixture(const wp::JointPredictorParams& params = wp::JointPredictorParams()) : predictor(arm, params) {
    add(0, Eigen::Vector3d(0.5, 0, 0), Eigen::Vector3d(0.5, 0.05, 0.05));
    add(1, Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d(0.3, 0.05, 0.05));
    add(2, Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d(0.1, 0.1, 0.1));
  }
  // The elbow and wrist (joints 1, 2) read standing at zero at kNow: a plan then moves only
  // the shoulder.
  void holdElbowAndWrist() {
    predictor.observe(1, kNow, 0.0, 0.0);
    predictor.observe(2, kNow, 0.0, 0.0);
  }
  void add(int link, const Eigen::Vector3d& at, const Eigen::Vector3d& half) {
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
    offset.translation() = at;
    bodies.push_back({link, offset, half});
    predictor.addBody(link, offset, half.norm());
  }
  // Every body's box corners and centre on the true motion q(t) vs the predicted path, dense.
  void expectWithinMargin(const std::function<void(double, double*)>& q_of_t, double horizon,
                          const Eigen::Isometry3d& base = Eigen::Isometry3d::Identity()) {
    double q[3];
    Eigen::Isometry3d links[3];
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const wp::JointBodyPath& path = predictor.body(static_cast<int>(b));
      ASSERT_EQ(path.state, wp::JointPathState::kMoving) << path.why;
      ASSERT_GE(path.segments.size(), 1u);
      for (int s = 0; s <= 4000; ++s) {
        const double t = horizon * s / 4000.0;
        q_of_t(t, q);
        arm->forward(q, links);
        const Eigen::Isometry3d truth = base * links[bodies[b].link] * bodies[b].offset;
        double margin = 0.0;
        const Eigen::Isometry3d predicted = pathPose(path.segments, t, &margin);
        for (const Eigen::Vector3d& c : corners(bodies[b].half)) {
          ASSERT_LE((truth * c - predicted * c).norm(), margin + 1e-9)
              << "body " << b << " t " << t << " margin " << margin;
        }
      }
      // Exact at every keyframe.
      for (const wp::MotionSegment& seg : path.segments) {
        q_of_t(seg.start, q);
        arm->forward(q, links);
        const Eigen::Isometry3d truth = base * links[bodies[b].link] * bodies[b].offset;
        EXPECT_LT((truth.translation() - seg.motion.position).norm(), 1e-9);
      }
    }
  }
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

TEST(JointPredictor, ConstantVelocitiesStayWithinTheStatedBound) {
  Fixture f;
  f.predictor.observe(0, kNow, 0.1, 0.8);
  f.predictor.observe(1, kNow, -0.2, -0.5);
  f.predictor.observe(2, kNow, 0.05, 0.0);
  f.predictor.predict(kNow, 1.0, wp::BodyMotion());
  EXPECT_GT(f.predictor.segmentCount(), 1);
  f.expectWithinMargin([](double t, double* q) {
    q[0] = 0.1 + 0.8 * t;
    q[1] = -0.2 - 0.5 * t;
    q[2] = 0.05;
  }, 1.0);
  // The bound is useful, not just safe: within the tolerance where the budget allows.
  for (int b = 0; b < 3; ++b) {
    for (const wp::MotionSegment& s : f.predictor.body(b).segments) EXPECT_LE(s.margin, 0.0101);
  }
}

TEST(JointPredictor, SlidingAndTurningTogetherOnAMovingBase) {
  Fixture f;
  f.predictor.observe(0, kNow, -0.5, 1.2);
  f.predictor.observe(1, kNow, 0.3, -0.6);
  f.predictor.observe(2, kNow, 0.0, 0.1);
  wp::BodyMotion base;
  base.position = Eigen::Vector3d(1, 2, 0);
  base.linear_velocity = Eigen::Vector3d(0.3, 0, 0);
  base.angular_velocity = Eigen::Vector3d(0, 0, 0.4);
  f.predictor.predict(kNow, 2.0, base);
  // The base's constant twist about its own origin, as BodyMotion::poseAt defines it.
  double q[3];
  Eigen::Isometry3d links[3];
  for (std::size_t b = 0; b < f.bodies.size(); ++b) {
    const wp::JointBodyPath& path = f.predictor.body(static_cast<int>(b));
    ASSERT_EQ(path.state, wp::JointPathState::kMoving);
    for (int s = 0; s <= 4000; ++s) {
      const double t = 2.0 * s / 4000.0;
      q[0] = -0.5 + 1.2 * t;
      q[1] = std::max(-1.0, 0.3 - 0.6 * t);
      q[2] = std::min(0.3, 0.1 * t);
      f.arm->forward(q, links);
      const Eigen::Isometry3d truth = base.poseAt(t) * links[f.bodies[b].link] * f.bodies[b].offset;
      double margin = 0.0;
      const Eigen::Isometry3d predicted = pathPose(path.segments, t, &margin);
      for (const Eigen::Vector3d& c : corners(f.bodies[b].half)) {
        ASSERT_LE((truth * c - predicted * c).norm(), margin + 1e-9) << "body " << b << " t " << t;
      }
    }
  }
}

TEST(JointPredictor, AJointStopsAtItsLimit) {
  Fixture f;
  // Shoulder at 1.5 rad turning at 1 rad/s: reaches its upper limit 2.0 at t = 0.5 and stays.
  f.predictor.observe(0, kNow, 1.5, 1.0);
  f.holdElbowAndWrist();
  f.predictor.predict(kNow, 2.0, wp::BodyMotion());
  f.expectWithinMargin([](double t, double* q) {
    q[0] = std::min(2.0, 1.5 + t);
    q[1] = 0.0;
    q[2] = 0.0;
  }, 2.0);
  // After the stop the upper arm stands exactly still at the limit: a segment starts at 0.5.
  const std::vector<wp::MotionSegment>& path = f.predictor.body(0).segments;
  const wp::MotionSegment& last = path.back();
  EXPECT_LE(last.start, 0.5 + 1e-6);
  EXPECT_LT(last.motion.angular_velocity.norm(), 1e-9);
  EXPECT_LT(last.motion.linear_velocity.norm(), 1e-9);
  EXPECT_EQ(last.margin, 0.0);
  EXPECT_NEAR(std::atan2(last.motion.position.y(), last.motion.position.x()), 2.0, 1e-9);
}

TEST(JointPredictor, FiniteDifferencesWhenVelocityIsNotMeasured) {
  Fixture f;
  for (int j = 0; j < 3; ++j) f.predictor.observe(j, kNow - kSecond / 10, 0.0, kNaN);
  f.predictor.predict(kNow - kSecond / 10, 1.0, wp::BodyMotion());
  // One reading, no velocity: posed where it is, but stale (never standing still).
  for (int b = 0; b < 3; ++b) {
    EXPECT_EQ(f.predictor.body(b).state, wp::JointPathState::kStale);
    EXPECT_NE(f.predictor.body(b).why.find("velocity"), std::string::npos);
    ASSERT_EQ(f.predictor.body(b).segments.size(), 1u);
  }
  f.predictor.observe(0, kNow, 0.05, kNaN);  // 0.5 rad/s
  f.predictor.observe(1, kNow, 0.0, kNaN);
  f.predictor.observe(2, kNow, 0.0, kNaN);
  f.predictor.predict(kNow, 1.0, wp::BodyMotion());
  f.expectWithinMargin([](double t, double* q) {
    q[0] = 0.05 + 0.5 * t;
    q[1] = 0.0;
    q[2] = 0.0;
  }, 1.0);
}

TEST(JointPredictor, LatencyIsCompensatedFromTheReadingsStamp) {
  Fixture f;
  f.predictor.observe(0, kNow - kSecond / 5, 0.0, 1.0);  // 0.2 s old: at 0.2 rad now
  f.holdElbowAndWrist();
  f.predictor.predict(kNow, 1.0, wp::BodyMotion());
  f.expectWithinMargin([](double t, double* q) {
    q[0] = 0.2 + t;
    q[1] = 0.0;
    q[2] = 0.0;
  }, 1.0);
}

TEST(JointPredictor, OldOrMissingReadingsLeaveTheirLinksUnknown) {
  wp::JointPredictorParams params;
  params.state_timeout = 0.5;
  Fixture f(params);
  f.predictor.observe(0, kNow, 0.0, 0.0);
  f.predictor.observe(1, kNow - kSecond, 0.0, 0.0);  // 1 s old
  f.predictor.predict(kNow, 1.0, wp::BodyMotion());
  EXPECT_EQ(f.predictor.body(0).state, wp::JointPathState::kMoving);
  EXPECT_EQ(f.predictor.body(1).state, wp::JointPathState::kUnknown);
  EXPECT_NE(f.predictor.body(1).why.find("elbow"), std::string::npos);
  EXPECT_EQ(f.predictor.body(2).state, wp::JointPathState::kUnknown);  // old elbow, or no slide
}

namespace {
// Plan for the shoulder: from 0 to 1 rad by 0.5 s, a stop until 1.0 s, back to 0.2 by 1.5 s.
wp::JointPlan shoulderPlan(wp::Stamp start) {
  wp::JointPlan plan;
  plan.start = start;
  plan.joints = {0};
  plan.times = {0.0, 0.5, 1.0, 1.5};
  plan.positions = {0.0, 1.0, 1.0, 0.2};
  return plan;
}
double shoulderPlanAt(double t) {
  if (t <= 0.5) return 2.0 * t;
  if (t <= 1.0) return 1.0;
  if (t <= 1.5) return 1.0 - 1.6 * (t - 1.0);
  return 0.2;
}
}  // namespace

TEST(JointPredictor, FollowsAPlanWithAStopAndHoldsItsEnd) {
  Fixture f;
  f.predictor.observe(0, kNow, 0.0, 0.0);  // standing, but the plan says it will move
  f.predictor.observe(1, kNow, 0.0, 0.4);  // not in the plan: its own velocity
  f.predictor.observe(2, kNow, 0.1, 0.0);
  ASSERT_EQ(f.predictor.setPlan(shoulderPlan(kNow), kNow), "");
  f.predictor.predict(kNow, 2.0, wp::BodyMotion());
  EXPECT_TRUE(f.predictor.hasPlan());
  f.expectWithinMargin([](double t, double* q) {
    q[0] = shoulderPlanAt(t);
    q[1] = std::min(1.0, 0.4 * t);
    q[2] = 0.1;
  }, 2.0);
  // Through the stop the upper arm stands exactly still.
  double margin = 0.0;
  const Eigen::Isometry3d a = pathPose(f.predictor.body(0).segments, 0.6, &margin);
  const Eigen::Isometry3d b = pathPose(f.predictor.body(0).segments, 0.9, &margin);
  EXPECT_LT((a.translation() - b.translation()).norm(), 1e-9);
}

TEST(JointPredictor, APlanInProgressStartsWhereThePlanIsNowNotWhereTheReadingWas) {
  // The plan began 0.9 s before the newest reading, which caught the shoulder in the stop
  // (1 rad, standing). The cycle runs 0.15 s later: by the plan the stop ended 0.05 s ago and
  // the shoulder is already on its way back (1 - 1.6 * 0.05 = 0.92 rad). Starting from the
  // stale reading would put the arm behind the plan, and its contacts late.
  Fixture f;
  const wp::Stamp start = kNow - 9 * kSecond / 10;
  f.predictor.observe(0, kNow, 1.0, 0.0);
  f.holdElbowAndWrist();
  ASSERT_EQ(f.predictor.setPlan(shoulderPlan(start), kNow), "");
  const wp::Stamp now = kNow + 3 * kSecond / 20;
  f.predictor.predict(now, 2.0, wp::BodyMotion());
  EXPECT_TRUE(f.predictor.hasPlan());
  f.expectWithinMargin([](double t, double* q) {
    q[0] = shoulderPlanAt(1.05 + t);
    q[1] = 0.0;
    q[2] = 0.0;
  }, 2.0);
}

TEST(JointPredictor, APlanStampedAheadStartsLater) {
  Fixture f;
  f.predictor.observe(0, kNow, 0.3, 0.0);
  f.holdElbowAndWrist();
  wp::JointPlan plan = shoulderPlan(kNow + kSecond / 2);
  plan.positions[0] = 0.3;  // its first point is where the arm is
  ASSERT_EQ(f.predictor.setPlan(plan, kNow), "");
  f.predictor.predict(kNow, 2.0, wp::BodyMotion());
  f.expectWithinMargin([](double t, double* q) {
    const double s = t - 0.5;
    q[0] = s <= 0.0 ? 0.3 : s <= 0.5 ? 0.3 + 1.4 * s : shoulderPlanAt(s);
    q[1] = 0.0;
    q[2] = 0.0;
  }, 2.0);
}

TEST(JointPredictor, BadPlansAreRefusedAndTheOneInForceStays) {
  Fixture f;
  ASSERT_EQ(f.predictor.setPlan(shoulderPlan(kNow), kNow), "");
  wp::JointPlan p = shoulderPlan(kNow);
  p.times = {0.0, 0.5, 0.5, 1.5};
  EXPECT_NE(f.predictor.setPlan(p, kNow), "");
  p = shoulderPlan(kNow);
  p.joints = {7};
  EXPECT_NE(f.predictor.setPlan(p, kNow), "");
  p = shoulderPlan(kNow);
  p.positions.pop_back();
  EXPECT_NE(f.predictor.setPlan(p, kNow), "");
  p = shoulderPlan(kNow - 3 * kSecond);  // ended 1.5 s ago
  EXPECT_NE(f.predictor.setPlan(p, kNow), "");
  p = shoulderPlan(kNow);
  p.positions[1] = kNaN;
  EXPECT_NE(f.predictor.setPlan(p, kNow), "");
  EXPECT_TRUE(f.predictor.hasPlan());
}

TEST(JointPredictor, APlanTheReadingsContradictIsDropped) {
  wp::JointPredictorParams params;
  params.trajectory_tolerance = 0.1;
  Fixture f(params);
  f.holdElbowAndWrist();
  ASSERT_EQ(f.predictor.setPlan(shoulderPlan(kNow), kNow), "");
  // At 0.25 s the plan has the shoulder at 0.5 rad: a reading of 0.45 is within tolerance.
  f.predictor.observe(0, kNow + kSecond / 4, 0.45, 0.0);
  f.predictor.predict(kNow + kSecond / 4, 2.0, wp::BodyMotion());
  EXPECT_TRUE(f.predictor.hasPlan());
  EXPECT_EQ(f.predictor.planEvent(), "");
  // At 0.3 s it should be at 0.6 rad; it is at 0.45 (stuck): dropped, its readings rule.
  f.predictor.observe(0, kNow + 3 * kSecond / 10, 0.45, 0.0);
  f.predictor.predict(kNow + 3 * kSecond / 10, 2.0, wp::BodyMotion());
  EXPECT_FALSE(f.predictor.hasPlan());
  EXPECT_NE(f.predictor.planEvent().find("shoulder"), std::string::npos);
  const wp::MotionSegment& s = f.predictor.body(0).segments.back();
  EXPECT_LT(s.motion.angular_velocity.norm(), 1e-9);
  EXPECT_NEAR(std::atan2(s.motion.position.y(), s.motion.position.x()), 0.45, 1e-9);
}

TEST(JointPredictor, ManyBreaksBeyondTheBudgetStayConservative) {
  wp::JointPredictorParams params;
  params.max_segments = 4;
  Fixture f(params);
  f.predictor.observe(1, kNow, 0.0, 0.3);
  f.predictor.observe(2, kNow, 0.0, 0.0);
  f.predictor.observe(0, kNow, 0.0, 0.0);
  wp::JointPlan plan;
  plan.start = kNow;
  plan.joints = {0};
  for (int k = 0; k <= 10; ++k) {
    plan.times.push_back(0.2 * k);
    plan.positions.push_back(k % 2 == 0 ? 0.0 : 0.8);
  }
  ASSERT_EQ(f.predictor.setPlan(plan, kNow), "");
  f.predictor.predict(kNow, 2.0, wp::BodyMotion());
  EXPECT_LE(f.predictor.segmentCount(), 4);
  f.expectWithinMargin([](double t, double* q) {
    const double u = std::fmod(t, 0.4);
    q[0] = u <= 0.2 ? 4.0 * u : 0.8 - 4.0 * (u - 0.2);
    q[1] = 0.3 * t;
    q[2] = 0.0;
  }, 2.0);
}

TEST(JointPredictor, SteadyStateCyclesAllocateNothing) {
  Fixture f;
  wp::JointPlan plan = shoulderPlan(kNow);
  plan.times = {0.0, 5.0, 10.0, 15.0};  // long enough to stay in force
  ASSERT_EQ(f.predictor.setPlan(plan, kNow), "");
  auto cycle = [&](int c) {
    const wp::Stamp now = kNow + c * kSecond / 30;
    const double t = c / 30.0;
    f.predictor.observe(0, now, std::min(1.0, 0.2 * t), t < 5.0 ? 0.2 : 0.0);  // as planned
    f.predictor.observe(1, now, 0.1 * std::sin(t), 0.1 * std::cos(t));
    f.predictor.observe(2, now, 0.1, kNaN);  // finite differences
    f.predictor.predict(now, 2.0, wp::BodyMotion());
  };
  for (int c = 0; c < 10; ++c) cycle(c);  // sizes the buffers
  const long before = wp_test::allocationCount();
  for (int c = 10; c < 200; ++c) cycle(c);
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
  EXPECT_TRUE(f.predictor.hasPlan());
  EXPECT_EQ(f.predictor.body(2).state, wp::JointPathState::kMoving);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
