// Box checks: every bad box is rejected with the right reason, good ones pass, nearly unit
// quaternions are normalised; and the level policy's thresholds.

#include <gtest/gtest.h>

#include <limits>
#include <set>
#include <string>

#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/level_policy.hpp"

namespace wp = workspace_proximity;

namespace {

wp::BoxObservation goodBox() {
  wp::BoxObservation b;
  b.id = "7";
  b.label = "person";
  b.position = {1.0, 2.0, 0.9};
  b.quaternion = {0, 0, 0, 1};
  b.dimensions = {0.5, 0.6, 1.8};
  b.linear_velocity = {1.2, 0, 0};
  b.angular_velocity = {0, 0, 0.3};
  return b;
}

template <typename Change>
wp::Drop verdict(Change change, const wp::BoxLimits& limits = wp::BoxLimits()) {
  wp::BoxObservation b = goodBox();
  change(b);
  std::string why;
  const wp::Drop d = wp::checkBox(b, limits, &why);
  // A rejection always explains itself.
  EXPECT_EQ(d == wp::Drop::kCount, why.empty()) << why;
  return d;
}

}  // namespace

TEST(BoxObservation, BadBoxesAreRejectedWithTheirReason) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  using wp::Drop;
  EXPECT_EQ(verdict([](wp::BoxObservation&) {}), Drop::kCount);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.id = ""; }), Drop::kEmptyId);
  EXPECT_EQ(verdict([&](wp::BoxObservation& b) { b.position.x() = nan; }), Drop::kNonFinite);
  EXPECT_EQ(verdict([&](wp::BoxObservation& b) { b.quaternion.z() = inf; }), Drop::kNonFinite);
  EXPECT_EQ(verdict([&](wp::BoxObservation& b) { b.angular_velocity.y() = nan; }), Drop::kNonFinite);
  EXPECT_EQ(verdict([&](wp::BoxObservation& b) { b.linear_velocity.x() = -inf; }), Drop::kNonFinite);
  EXPECT_EQ(verdict([&](wp::BoxObservation& b) { b.dimensions.y() = nan; }), Drop::kNonFinite);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.dimensions.x() = 0.0; }), Drop::kDimensions);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.dimensions.z() = -1.0; }), Drop::kDimensions);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.dimensions.x() = std::numeric_limits<double>::denorm_min(); }),
            Drop::kDimensions);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.dimensions.x() = 5000.0; }), Drop::kDimensions);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.position.y() = 1e7; }), Drop::kPosition);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.quaternion.w() = 0.0; }), Drop::kOrientation);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.quaternion.w() = 2.0; }), Drop::kOrientation);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.linear_velocity.x() = 500.0; }), Drop::kSpeed);
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.angular_velocity.z() = 500.0; }), Drop::kAngularSpeed);
  EXPECT_EQ(verdict([](wp::BoxObservation&) {}, wp::BoxLimits{1000.0, 0.5, 100.0, 100.0, 0.01}),
            Drop::kPosition);
}

TEST(BoxObservation, NearlyUnitQuaternionsAreNormalisedNotRejected) {
  EXPECT_EQ(verdict([](wp::BoxObservation& b) { b.quaternion.w() = 1.004; }), wp::Drop::kCount);
  wp::BoxObservation nearly = goodBox();
  nearly.quaternion.w() = 1.004;
  EXPECT_NEAR(wp::boxMotion(nearly, Eigen::Isometry3d::Identity()).orientation.norm(), 1.0, 1e-12);
}

TEST(BoxObservation, FrameTransformMovesPoseAndRotatesTwist) {
  Eigen::Isometry3d fixed_from_frame = Eigen::Isometry3d::Identity();
  fixed_from_frame.translation() = Eigen::Vector3d(10, 0, 0);
  fixed_from_frame.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const wp::BodyMotion m = wp::boxMotion(goodBox(), fixed_from_frame);
  EXPECT_TRUE(m.position.isApprox(Eigen::Vector3d(8, 1, 0.9), 1e-12));
  EXPECT_TRUE(m.linear_velocity.isApprox(Eigen::Vector3d(0, 1.2, 0), 1e-12));
  EXPECT_TRUE(m.angular_velocity.isApprox(Eigen::Vector3d(0, 0, 0.3), 1e-12));
  EXPECT_TRUE(wp::boxShape(goodBox()).half_extents.isApprox(Eigen::Vector3d(0.25, 0.3, 0.9), 1e-15));
}

TEST(BoxObservation, EveryDropReasonHasItsOwnName) {
  std::set<std::string> names;
  for (int i = 0; i < static_cast<int>(wp::Drop::kCount); ++i) {
    names.insert(wp::dropName(static_cast<wp::Drop>(i)));
  }
  EXPECT_EQ(names.size(), static_cast<std::size_t>(wp::Drop::kCount));
  EXPECT_STREQ(wp::dropName(wp::Drop::kNonFinite), "non-finite");
  EXPECT_STREQ(wp::dropName(wp::Drop::kDuplicateId), "duplicate id");
  EXPECT_STREQ(wp::dropName(wp::Drop::kCoreLimits), "core limits");
  EXPECT_STREQ(wp::dropName(wp::Drop::kSuperseded), "superseded");
}

TEST(LevelPolicy, LevelsFollowTheStricterThreshold) {
  wp::LabelSettings person;  // warning 1.0 s / 0.5 m, critical 0.4 s / 0.2 m
  wp::LabelSettings lax;
  lax.warning_time = 0.1;
  lax.critical_time = 0.05;
  lax.warning_distance = 0.01;
  lax.critical_distance = 0.0;
  wp::PairEvent e;
  e.distance = 2.0;
  e.time_to_contact = 1.5;
  EXPECT_EQ(wp::contactLevel(e, person, lax), wp::Level::kNotice);
  e.time_to_contact = 0.9;
  EXPECT_EQ(wp::contactLevel(e, person, lax), wp::Level::kWarning);
  EXPECT_EQ(wp::contactLevel(e, lax, lax), wp::Level::kNotice);
  e.time_to_contact = 0.3;
  EXPECT_EQ(wp::contactLevel(e, lax, person), wp::Level::kCritical);
  e.time_to_contact = 5.0;
  e.distance = 0.1;
  EXPECT_EQ(wp::contactLevel(e, person, lax), wp::Level::kCritical);
  // Thresholds are inclusive.
  e.distance = 0.5;
  EXPECT_EQ(wp::contactLevel(e, person, person), wp::Level::kWarning);
  e.state = wp::ContactState::kEnd;
  EXPECT_EQ(wp::contactLevel(e, person, person), wp::Level::kNotice);
}

TEST(LevelPolicy, LabelTableFindsListedLabelsAndFallsBackToDefault) {
  wp::MonitorParams p;
  p.labels["default"].warning_time = 1.1;
  p.labels["person"].warning_time = 2.2;
  p.labels["forklift"].warning_time = 3.3;
  p.robot_thresholds.warning_time = 0.7;
  const wp::LabelTable t(p);
  EXPECT_EQ(t.settings(wp::LabelTable::kRobot).warning_time, 0.7);
  EXPECT_EQ(t.settings(t.indexOf("person")).warning_time, 2.2);
  EXPECT_EQ(t.settings(t.indexOf("forklift")).warning_time, 3.3);
  EXPECT_EQ(t.indexOf("cart"), wp::LabelTable::kDefault);
  EXPECT_EQ(t.settings(t.indexOf("cart")).warning_time, 1.1);
  EXPECT_EQ(t.indexOf(""), wp::LabelTable::kDefault);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
