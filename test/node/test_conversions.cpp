// Conversions between messages and the core: round trips and rejection of bad boxes.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "workspace_proximity/ros/conversions.hpp"

namespace wp = workspace_proximity;

namespace {

wp::TrackedBox goodBox() {
  wp::TrackedBox b;
  b.id = "7";
  b.label = "person";
  b.pose.position.x = 1.0;
  b.pose.position.y = 2.0;
  b.pose.position.z = 0.9;
  b.pose.orientation.w = 1.0;
  b.dimensions.x = 0.5;
  b.dimensions.y = 0.6;
  b.dimensions.z = 1.8;
  b.twist.linear.x = 1.2;
  b.twist.angular.z = 0.3;
  return b;
}

}  // namespace

TEST(Conversions, TrackedBoxRoundTripsThroughTheCore) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-5, 5), s(0.1, 3);
  for (int i = 0; i < 500; ++i) {
    wp::BodyMotion m;
    m.position = {u(rng), u(rng), u(rng)};
    m.orientation = Eigen::Quaterniond::UnitRandom();
    m.linear_velocity = {u(rng), u(rng), u(rng)};
    m.angular_velocity = {u(rng), u(rng), u(rng)};
    const wp::Shape shape = wp::Shape::box({s(rng), s(rng), s(rng)});
    const wp::TrackedBox box = wp::toTrackedBox("id", "label", shape, m);
    ASSERT_EQ(wp::checkTrackedBox(box), "");
    const wp::BodyMotion back = wp::toMotion(box, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(back.position.isApprox(m.position, 1e-12));
    EXPECT_NEAR(std::abs(back.orientation.dot(m.orientation)), 1.0, 1e-12);
    EXPECT_TRUE(back.linear_velocity.isApprox(m.linear_velocity, 1e-12));
    EXPECT_TRUE(back.angular_velocity.isApprox(m.angular_velocity, 1e-12));
    EXPECT_TRUE(wp::toShape(box).half_extents.isApprox(shape.half_extents, 1e-12));
  }
}

TEST(Conversions, FrameTransformMovesPoseAndRotatesTwist) {
  wp::TrackedBox box = goodBox();
  Eigen::Isometry3d fixed_from_frame = Eigen::Isometry3d::Identity();
  fixed_from_frame.translation() = Eigen::Vector3d(10, 0, 0);
  fixed_from_frame.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const wp::BodyMotion m = wp::toMotion(box, fixed_from_frame);
  EXPECT_TRUE(m.position.isApprox(Eigen::Vector3d(8, 1, 0.9), 1e-12));
  EXPECT_TRUE(m.linear_velocity.isApprox(Eigen::Vector3d(0, 1.2, 0), 1e-12));
  EXPECT_TRUE(m.angular_velocity.isApprox(Eigen::Vector3d(0, 0, 0.3), 1e-12));
}

TEST(Conversions, PairEventRoundTripsThroughTheMessage) {
  wp::PairEvent e;
  e.state = wp::ContactState::kOngoing;
  e.time_to_contact = 0.75;
  e.time_to_separation = 1.5;
  e.distance = 0.3;
  e.point_a = {1, 2, 3};
  e.point_b = {1.3, 2, 3};
  e.normal = {1, 0, 0};
  e.closing_speed = 0.4;
  wp::BodyDesc a, b;
  a.id = "arm";
  a.label = "robot";
  b.id = "bob";
  b.label = "person";
  const wp::ContactEvent msg = wp::toMsg(e, a, b, wp::ContactEvent::WARNING);
  EXPECT_EQ(msg.id_a, "arm");
  EXPECT_EQ(msg.label_b, "person");
  EXPECT_EQ(msg.state, wp::ContactEvent::ONGOING);
  EXPECT_EQ(msg.level, wp::ContactEvent::WARNING);
  const wp::PairEvent back = wp::fromMsg(msg);
  EXPECT_EQ(back.state, e.state);
  EXPECT_EQ(back.time_to_contact, e.time_to_contact);
  EXPECT_EQ(back.time_to_separation, e.time_to_separation);
  EXPECT_EQ(back.distance, e.distance);
  EXPECT_EQ(back.point_a, e.point_a);
  EXPECT_EQ(back.point_b, e.point_b);
  EXPECT_EQ(back.normal, e.normal);
  EXPECT_EQ(back.closing_speed, e.closing_speed);
}

TEST(Conversions, LevelsFollowTheStricterThreshold) {
  wp::LabelSettings person;  // warning 1.0 s / 0.5 m, critical 0.4 s / 0.2 m
  wp::LabelSettings lax;
  lax.warning_time = 0.1;
  lax.critical_time = 0.05;
  lax.warning_distance = 0.01;
  lax.critical_distance = 0.0;
  wp::PairEvent e;
  e.distance = 2.0;
  e.time_to_contact = 1.5;
  EXPECT_EQ(wp::contactLevel(e, person, lax), wp::ContactEvent::NOTICE);
  e.time_to_contact = 0.9;
  EXPECT_EQ(wp::contactLevel(e, person, lax), wp::ContactEvent::WARNING);
  EXPECT_EQ(wp::contactLevel(e, lax, lax), wp::ContactEvent::NOTICE);
  e.time_to_contact = 0.3;
  EXPECT_EQ(wp::contactLevel(e, lax, person), wp::ContactEvent::CRITICAL);
  e.time_to_contact = 5.0;
  e.distance = 0.1;
  EXPECT_EQ(wp::contactLevel(e, person, lax), wp::ContactEvent::CRITICAL);
  e.state = wp::ContactState::kEnd;
  EXPECT_EQ(wp::contactLevel(e, person, person), wp::ContactEvent::NOTICE);
}

TEST(Conversions, BadBoxesAreRejectedWithAReason) {
  EXPECT_EQ(wp::checkTrackedBox(goodBox()), "");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  auto with = [](auto change) {
    wp::TrackedBox b = goodBox();
    change(b);
    return wp::checkTrackedBox(b);
  };
  EXPECT_NE(with([](wp::TrackedBox& b) { b.id.clear(); }), "");
  EXPECT_NE(with([&](wp::TrackedBox& b) { b.pose.position.x = nan; }), "");
  EXPECT_NE(with([&](wp::TrackedBox& b) { b.pose.orientation.z = inf; }), "");
  EXPECT_NE(with([&](wp::TrackedBox& b) { b.twist.angular.y = nan; }), "");
  EXPECT_NE(with([&](wp::TrackedBox& b) { b.dimensions.y = nan; }), "");
  EXPECT_NE(with([](wp::TrackedBox& b) { b.dimensions.x = 0.0; }), "");
  EXPECT_NE(with([](wp::TrackedBox& b) { b.dimensions.z = -1.0; }), "");
  EXPECT_NE(with([](wp::TrackedBox& b) { b.dimensions.x = 5000.0; }), "");
  EXPECT_NE(with([](wp::TrackedBox& b) { b.pose.position.y = 1e7; }), "");
  EXPECT_NE(with([](wp::TrackedBox& b) { b.pose.orientation.w = 0.0; }), "");
  EXPECT_NE(with([](wp::TrackedBox& b) { b.pose.orientation.w = 2.0; }), "");
  // Nearly unit quaternions are normalised, not rejected.
  EXPECT_EQ(with([](wp::TrackedBox& b) { b.pose.orientation.w = 1.004; }), "");
  wp::TrackedBox nearly = goodBox();
  nearly.pose.orientation.w = 1.004;
  EXPECT_NEAR(wp::toMotion(nearly, Eigen::Isometry3d::Identity()).orientation.norm(), 1.0, 1e-12);
  EXPECT_NE(with([](wp::TrackedBox& b) { b.twist.linear.x = 500.0; }), "");
  EXPECT_NE(wp::checkTrackedBox(goodBox(), wp::BoxLimits{1000.0, 0.5, 100.0, 100.0, 0.01}), "");
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
