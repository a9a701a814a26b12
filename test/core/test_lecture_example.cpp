// The lecture's worked example, exactly: two boxes of width 2; A at (1, 1) moving (4, 3),
// B at (4, 2) moving (-1, 0), over one frame (t in [0, 1]). On x, first contact is at 1/5 of
// the frame and last contact at 1. Checked on the per-axis formula and through the whole
// pipeline (broad phase, per-axis time of impact, FCL narrow phase, events).

#include <gtest/gtest.h>

#include "workspace_proximity/proximity_world.hpp"
#include "workspace_proximity/time_of_impact.hpp"

namespace wp = workspace_proximity;

TEST(LectureExample, XAxisFirstContactAtOneFifthLastAtOne) {
  // A spans x in [0, 2], B spans [3, 5].
  const wp::TimeInterval x = wp::axisContactInterval(0.0, 2.0, 4.0, 3.0, 5.0, -1.0);
  // Exact up to the library's outward widening by a few ulps: never narrower than the truth.
  EXPECT_LE(x.first, 0.2);
  EXPECT_GE(x.first, 0.2 - 1e-9);
  EXPECT_GE(x.last, 1.0);
  EXPECT_LE(x.last, 1.0 + 1e-9);
}

TEST(LectureExample, YAxisAlreadyOverlapsAndLeavesAtOne) {
  // A spans y in [0, 2] moving +3; B spans [1, 3] at rest: overlapping now, A's lower edge
  // passes B's upper edge (3) at t = 1.
  const wp::TimeInterval y = wp::axisContactInterval(0.0, 2.0, 3.0, 1.0, 3.0, 0.0);
  EXPECT_LE(y.first, 0.0);
  EXPECT_GE(y.last, 1.0);
  EXPECT_LE(y.last, 1.0 + 1e-9);
}

TEST(LectureExample, BoxIntervalIsTheIntersectionClippedToTheFrame) {
  const wp::TimeInterval box = wp::boxContactInterval(
      {1, 1, 0}, {1, 1, 1}, {4, 3, 0}, {4, 2, 0}, {1, 1, 1}, {-1, 0, 0}, 1.0);
  ASSERT_FALSE(box.empty());
  EXPECT_LE(box.first, 0.2);
  EXPECT_GE(box.first, 0.2 - 1e-9);
  EXPECT_DOUBLE_EQ(box.last, 1.0);  // clipped to the frame
}

TEST(LectureExample, WholePipelineReportsContactAtOneFifthOfTheFrame) {
  wp::ProximityWorld world;
  wp::BodyMotion a, b;
  a.position = {1, 1, 0};
  a.linear_velocity = {4, 3, 0};
  b.position = {4, 2, 0};
  b.linear_velocity = {-1, 0, 0};
  const wp::Shape cube = wp::Shape::box({1, 1, 1});
  const wp::BodyHandle ha = world.addBody({"A", "box", wp::BodyGroup::kObject, cube, 0.0}, a);
  world.addBody({"B", "box", wp::BodyGroup::kObject, cube, 0.0}, b);

  const auto& events = world.predict(1.0);
  ASSERT_EQ(events.size(), 1u);
  const wp::PairEvent& e = events[0];
  EXPECT_EQ(e.state, wp::ContactState::kBegin);
  EXPECT_EQ(e.body_a, ha);  // "A" < "B"
  // Exact answer 0.2 of the frame; the narrow phase may only be early, by well under 1 ms.
  EXPECT_LE(e.time_to_contact, 0.2 + 1e-12);
  EXPECT_GE(e.time_to_contact, 0.2 - 1e-3);
  // Last contact: both the x and y overlaps end at t = 1; may only be late.
  EXPECT_GE(e.time_to_separation, 1.0 - 1e-12);
  EXPECT_LE(e.time_to_separation, 1.0 + 1e-3);
  // Now: gap of 1 m on x (A's right face at 2, B's left face at 3).
  EXPECT_NEAR(e.distance, 1.0, 1e-6);
  EXPECT_NEAR(e.normal.x(), 1.0, 1e-6);
  // Closing speed along x: 4 - (-1) = 5 m/s.
  EXPECT_NEAR(e.closing_speed, 5.0, 1e-6);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
