// ForeignObservations (foreign_observations.hpp): foreign people tracks as box observations.
// Oracles: covariances built from known eigenvalues and rotations (the 3 sigma bound is three
// times the root of the largest), positions moved by known velocities over known times (the
// finite difference is exact for constant velocity), and the label table's sizes.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "allocation_counter.hpp"
#include "workspace_proximity/rules/foreign_observations.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;

wp::ForeignTrack person(std::uint64_t id, const Eigen::Vector3d& position, wp::Stamp stamp) {
  wp::ForeignTrack t;
  t.id_kind = wp::ForeignIdKind::kNumber;
  t.id_number = id;
  t.label = "person";
  t.stamp = stamp;
  t.frame_id = "map";
  t.position = position;
  return t;
}

}  // namespace

TEST(ForeignObservations, ThreeSigmaIsThreeRootsOfTheLargestEigenvalue) {
  // Eigenvalues 0.04, 0.01, 0.0025 (sigmas 0.2, 0.1, 0.05) in a rotated basis.
  const Eigen::Matrix3d r =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Matrix3d c = r * Eigen::Vector3d(0.04, 0.01, 0.0025).asDiagonal() * r.transpose();
  EXPECT_NEAR(wp::threeSigma(c, wp::kAxesAll), 0.6, 1e-12);
  // Only x and y known: the largest eigenvalue of the 2x2 block, by its closed form.
  const double a = c(0, 0), b = c(0, 1), d = c(1, 1);
  const double largest = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b);
  EXPECT_NEAR(wp::threeSigma(c, wp::kAxesXY), 3.0 * std::sqrt(largest), 1e-12);
  EXPECT_EQ(wp::threeSigma(c, wp::kAxesNone), 0.0);
}

TEST(ForeignObservations, LabelsSizesIdsAndErrors) {
  wp::MonitorParams params;
  wp::LabelSettings cart;
  cart.size_x = 1.0;
  cart.size_y = 0.5;
  cart.size_z = 0.8;
  params.labels["cart"] = cart;
  wp::ForeignTrackArray in(8);
  in.tracks.push_back(person(18446744073709551615ull, Eigen::Vector3d(1, 2, 0.9), kSecond));
  in.tracks.back().velocity = Eigen::Vector3d(0.5, -0.25, 0);
  in.tracks.back().velocity_axes = wp::kAxesXY;
  in.tracks.back().has_position_covariance = true;
  in.tracks.back().position_covariance = Eigen::Vector3d(0.01, 0.04, 0).asDiagonal();
  in.tracks.back().position_axes = wp::kAxesXY;
  in.tracks.back().has_velocity_covariance = true;
  in.tracks.back().velocity_covariance = Eigen::Vector3d(0.09, 0.01, 0).asDiagonal();
  in.tracks.back().velocity_axes = wp::kAxesXY;
  wp::ForeignTrack cart_track = person(7, Eigen::Vector3d(3, 0, 0.4), kSecond);
  cart_track.label = "cart";
  cart_track.dimensions = Eigen::Vector3d(2.0, 0, 0);
  cart_track.dimension_axes = 0b001;  // x given, y and z from the label
  in.tracks.push_back(cart_track);
  wp::ForeignTrack pedestrian = person(8, Eigen::Vector3d(0, 0, 0), kSecond);
  pedestrian.label = "pedestrian";
  in.tracks.push_back(pedestrian);
  wp::ForeignTrack elsewhere = person(9, Eigen::Vector3d(0, 0, 0), kSecond);
  elsewhere.frame_id = "odom";
  in.tracks.push_back(elsewhere);

  wp::ForeignObservations convert(8);
  std::vector<wp::BoxObservation> out;
  convert.convert(in, "map", params, &out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(convert.skippedFrame(), 1u);
  EXPECT_EQ(out[0].id, "18446744073709551615");
  EXPECT_EQ(out[0].label, "person");
  EXPECT_EQ(out[0].dimensions, Eigen::Vector3d(0.6, 0.6, 1.8));  // the default person
  EXPECT_TRUE(out[0].velocity_known);
  EXPECT_EQ(out[0].linear_velocity, Eigen::Vector3d(0.5, -0.25, 0));
  EXPECT_NEAR(out[0].position_error, 3.0 * 0.2, 1e-12);
  EXPECT_NEAR(out[0].velocity_error, 3.0 * 0.3, 1e-12);
  EXPECT_EQ(out[1].id, "7");
  EXPECT_EQ(out[1].dimensions, Eigen::Vector3d(2.0, 0.5, 0.8));
  EXPECT_EQ(out[1].position_error, 0.0);  // no covariance: the label's
  EXPECT_FALSE(out[1].velocity_known);    // first sighting, no velocity in the message
  EXPECT_EQ(out[2].label, "person");
}

TEST(ForeignObservations, UnsetPositionAxes) {
  // spencer's "unset" axes (variance above 99999) read 0 with their bit cleared.
  wp::MonitorParams params;
  wp::ForeignTrackArray in(4);
  in.tracks.push_back(person(1, Eigen::Vector3d(2, 3, 0), kSecond));
  in.tracks.back().position_axes = wp::kAxesXY;  // z unset: stands on z = 0
  in.tracks.push_back(person(2, Eigen::Vector3d(2, 0, 0.5), kSecond));
  in.tracks.back().position_axes = 0b101;  // y unset: where it is is unknown
  in.tracks.push_back(person(3, Eigen::Vector3d(0, 0, 0), kSecond));
  in.tracks.back().position_axes = wp::kAxesNone;
  wp::ForeignObservations convert(4);
  std::vector<wp::BoxObservation> out;
  convert.convert(in, "map", params, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(convert.skippedPosition(), 2u);
  EXPECT_EQ(out[0].id, "1");
  EXPECT_EQ(out[0].position, Eigen::Vector3d(2, 3, 0.9));  // half the person's 1.8 m
}

TEST(ForeignObservations, FiniteDifferencesOverTheIdAndNoAllocation) {
  wp::MonitorParams params;
  params.track_timeout = 0.5;
  const Eigen::Vector3d v(1.2, -0.4, 0.0);
  wp::ForeignObservations convert(4);
  wp::ForeignTrackArray in(4);
  std::vector<wp::BoxObservation> out;
  out.reserve(4);
  auto frame = [&](wp::Stamp t, bool with_second) {
    in.tracks.clear();
    const double s = static_cast<double>(t) * 1e-9;
    in.tracks.push_back(person(1, Eigen::Vector3d(1, 1, 0.9) + v * s, t));
    if (with_second) in.tracks.push_back(person(2, Eigen::Vector3d(4, 0, 0.9) - v * s, t));
    convert.convert(in, "map", params, &out);
  };
  frame(kSecond, false);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].velocity_known);
  EXPECT_EQ(out[0].linear_velocity, Eigen::Vector3d::Zero());
  const long before = wp_test::allocationCount();
  frame(kSecond + kSecond / 10, true);
  const long after = wp_test::allocationCount();
  EXPECT_EQ(after, before) << "converting allocated";
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].velocity_known);
  EXPECT_LT((out[0].linear_velocity - v).norm(), 1e-9);
  EXPECT_FALSE(out[1].velocity_known);  // track 2's first sighting
  frame(kSecond + 2 * kSecond / 10, true);
  EXPECT_LT((out[1].linear_velocity + v).norm(), 1e-9);
  // A gap longer than track_timeout: the old sighting is no longer a velocity.
  frame(kSecond + 9 * kSecond / 10, true);
  EXPECT_FALSE(out[0].velocity_known);
  EXPECT_FALSE(out[1].velocity_known);
  // After a reset the history is gone.
  frame(kSecond + 10 * kSecond / 10, true);
  EXPECT_TRUE(out[0].velocity_known);
  convert.reset();
  frame(kSecond + 11 * kSecond / 10, true);
  EXPECT_FALSE(out[0].velocity_known);
}

TEST(ForeignObservations, DifferencedVelocityCarriesThePositionErrors) {
  // Two positions each within p of the truth: their difference over dt within 2 p / dt.
  wp::MonitorParams params;
  params.labels["person"].max_speed = 5.0;  // the unknown-velocity speed: 3 m/s is better
  wp::ForeignObservations convert(2);
  wp::ForeignTrackArray in(2);
  std::vector<wp::BoxObservation> out;
  for (wp::Stamp t : {kSecond, kSecond + kSecond / 5}) {
    in.tracks.clear();
    in.tracks.push_back(person(3, Eigen::Vector3d::Zero(), t));
    in.tracks.back().has_position_covariance = true;
    in.tracks.back().position_covariance = 0.01 * Eigen::Matrix3d::Identity();
    convert.convert(in, "map", params, &out);
  }
  ASSERT_EQ(out.size(), 1u);
  EXPECT_TRUE(out[0].velocity_known);
  EXPECT_NEAR(out[0].position_error, 0.3, 1e-12);
  EXPECT_NEAR(out[0].velocity_error, 2.0 * 0.3 / 0.2, 1e-9);
  // 50 ms later the difference's error is 12 m/s, worse than growing at max_speed: unknown.
  in.tracks.clear();
  in.tracks.push_back(person(3, Eigen::Vector3d::Zero(), kSecond + kSecond / 4));
  in.tracks.back().has_position_covariance = true;
  in.tracks.back().position_covariance = 0.01 * Eigen::Matrix3d::Identity();
  convert.convert(in, "map", params, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].velocity_known);
  EXPECT_EQ(out[0].linear_velocity, Eigen::Vector3d::Zero());
}

TEST(ForeignObservations, ElementsStampedApartAreCarriedToTheMessagesStamp) {
  // A message stamped 2 s whose elements carry their own stamps (person label: position error
  // 0.05 m, velocity error 0.3 m/s, max_accel 4 m/s^2, max_speed 2 m/s). Hand-worked:
  // - A, 0.1 s older, moving at 1 m/s along x: carried 0.1 m along x; its error
  //   0.05 + min(0.3 * 0.1 + 4 * 0.1^2 / 2, (2 + 1) * 0.1) = 0.05 + 0.05 = 0.10 m;
  // - B, 0.1 s newer, velocity unknown: where it is, 0.05 + 2 * 0.1 = 0.25 m;
  // - C, at the message's stamp: as given (no error of its own).
  wp::MonitorParams params;
  wp::LabelSettings& settings = params.labels["person"];
  settings.position_error = 0.05;
  settings.velocity_error = 0.3;
  settings.max_accel = 4.0;
  settings.max_speed = 2.0;
  wp::ForeignObservations convert(4);
  wp::ForeignTrackArray in(4);
  in.stamp = 2 * kSecond;
  in.frame_id = "map";
  in.tracks.push_back(person(1, Eigen::Vector3d(1, 0, 0.9), 2 * kSecond - kSecond / 10));
  in.tracks.back().velocity = Eigen::Vector3d(1, 0, 0);
  in.tracks.back().velocity_axes = wp::kAxesAll;
  in.tracks.push_back(person(2, Eigen::Vector3d(3, 0, 0.9), 2 * kSecond + kSecond / 10));
  in.tracks.push_back(person(3, Eigen::Vector3d(5, 0, 0.9), 2 * kSecond));
  std::vector<wp::BoxObservation> out;
  convert.convert(in, "map", params, &out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_LT((out[0].position - Eigen::Vector3d(1.1, 0, 0.9)).norm(), 1e-12);
  EXPECT_NEAR(out[0].position_error, 0.10, 1e-12);
  EXPECT_TRUE(out[0].velocity_known);
  EXPECT_LT((out[1].position - Eigen::Vector3d(3, 0, 0.9)).norm(), 1e-12);
  EXPECT_NEAR(out[1].position_error, 0.25, 1e-12);
  EXPECT_FALSE(out[1].velocity_known);
  EXPECT_LT((out[2].position - Eigen::Vector3d(5, 0, 0.9)).norm(), 1e-12);
  EXPECT_EQ(out[2].position_error, 0.0);
  // Without a header stamp the first element's is the message's: A as given, C 0.1 s newer.
  in.stamp = 0;
  wp::ForeignObservations again(4);
  again.convert(in, "map", params, &out);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_LT((out[0].position - Eigen::Vector3d(1, 0, 0.9)).norm(), 1e-12);
  EXPECT_EQ(out[0].position_error, 0.0);
  EXPECT_NEAR(out[2].position_error, 0.05 + 2.0 * 0.1, 1e-12);  // unknown velocity, 0.1 s
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
