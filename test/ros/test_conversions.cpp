// Conversions between messages and the monitor/core: round trips, and the contacts message
// rendered from a cycle's report.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <tuple>

#include "workspace_proximity/ros/contact_publisher.hpp"
#include "workspace_proximity/ros/conversions.hpp"
#include "workspace_proximity/ros/reconfigure_bridge.hpp"
#include "workspace_proximity/ros/ssm_publisher.hpp"
#include "workspace_proximity/ros/twist_filter.hpp"
#include "workspace_proximity/rules/track_table.hpp"

namespace wp = workspace_proximity;

TEST(Conversions, TrackedBoxRoundTripsThroughTheMonitor) {
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
    const wp::BoxObservation seen = wp::observe(box);
    EXPECT_EQ(seen.id, "id");
    EXPECT_EQ(seen.label, "label");
    std::string why;
    ASSERT_EQ(wp::checkBox(seen, wp::BoxLimits(), &why), wp::Drop::kCount) << why;
    const wp::BodyMotion back = wp::boxMotion(seen, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(back.position.isApprox(m.position, 1e-12));
    EXPECT_NEAR(std::abs(back.orientation.dot(m.orientation)), 1.0, 1e-12);
    EXPECT_TRUE(back.linear_velocity.isApprox(m.linear_velocity, 1e-12));
    EXPECT_TRUE(back.angular_velocity.isApprox(m.angular_velocity, 1e-12));
    EXPECT_TRUE(wp::boxShape(seen).half_extents.isApprox(shape.half_extents, 1e-12));
  }
}

TEST(Conversions, ObservationViewsTheMessageWithoutCopies) {
  wp::TrackedBox box;
  box.id = "a rather long track id that no small-string buffer holds";
  box.label = "person";
  const wp::BoxObservation seen = wp::observe(box);
  EXPECT_EQ(seen.id.data(), box.id.data());
  EXPECT_EQ(seen.label.data(), box.label.data());
}

// TrackedBox's optional errors (issue 23) reach the track's body: zeros are the label's
// settings (every array before these fields), a larger own error widens the margin and its
// growth by the analytic amount, velocity_unknown grows it at the label's max_speed.
TEST(Conversions, TrackedBoxErrorsWidenTheMarginByTheAnalyticAmount) {
  wp::MonitorParams p;
  wp::LabelSettings& person = p.labels["person"];
  person.margin = 0.1;
  person.position_error = 0.05;
  person.velocity_error = 0.2;
  person.max_accel = 1.0;
  person.max_speed = 2.0;
  const wp::LabelTable labels(p);
  wp::ProximityWorld world;
  wp::DropCounters drops;
  wp::TrackTable table(&world, &labels, 10, wp::BoxLimits(), &drops, nullptr);

  // Three boxes, the same but for the new fields; the person walks at 0.5 m/s.
  std::vector<wp::TrackedBox> msgs(3);
  const char* ids[] = {"old", "own", "unknown"};
  for (int i = 0; i < 3; ++i) {
    msgs[i].id = ids[i];
    msgs[i].label = "person";
    msgs[i].pose.position.x = 2.0 * i;
    msgs[i].pose.orientation.w = 1.0;
    msgs[i].dimensions.x = msgs[i].dimensions.y = 0.6;
    msgs[i].dimensions.z = 1.8;
    msgs[i].twist.linear.x = 0.5;
  }
  msgs[1].position_error = 0.3;
  msgs[1].velocity_error = 0.6;
  msgs[2].velocity_unknown = true;
  std::vector<wp::BoxObservation> boxes;
  for (const wp::TrackedBox& m : msgs) boxes.push_back(wp::observe(m));
  EXPECT_EQ(boxes[0].position_error, 0.0);
  EXPECT_TRUE(boxes[0].velocity_known);
  EXPECT_FALSE(boxes[2].velocity_known);

  constexpr wp::Stamp kSecond = 1000000000;
  wp::ArrayContext a;
  a.source = "/boxes";
  a.stamp = 10 * kSecond;
  ASSERT_EQ(table.ingest(a, boxes), 3);
  table.advance(a.stamp + kSecond / 2);  // predicted 0.5 s after the measurement
  const double s = 0.5;
  // By hand: margin + max(label's position_error, own); R(s) = min(e s + a s^2 / 2,
  // (max_speed + |v|) s) with e = max(label's velocity_error, own); unknown: max_speed s.
  const double margin[] = {0.1 + 0.05, 0.1 + 0.3, 0.1 + 0.05};
  const double growth[] = {0.2 * s + 0.5 * 1.0 * s * s, 0.6 * s + 0.5 * 1.0 * s * s, 2.0 * s};
  for (int i = 0; i < 3; ++i) {
    const wp::Track& t = table.track(table.find(ids[i]));
    SCOPED_TRACE(ids[i]);
    EXPECT_NEAR(world.desc(t.handle).margin, margin[i], 1e-12);
    EXPECT_NEAR(world.growth(t.handle).at(0.0), growth[i], 1e-12);
  }
  // The own errors widen the old box's margin by 0.25 m and its growth by 0.2 m at 0.5 s.
  EXPECT_NEAR(margin[1] - margin[0], 0.25, 1e-12);
  EXPECT_NEAR(growth[1] - growth[0], 0.2, 1e-12);
  // An unknown velocity is predicted standing still.
  EXPECT_EQ(world.motion(table.track(table.find("unknown")).handle).linear_velocity.norm(), 0.0);
}

// NaN and negative errors are rejected by name; the rest of the box is fine.
TEST(Conversions, TrackedBoxBadErrorsAreRejectedByName) {
  wp::TrackedBox box;
  box.id = "a";
  box.label = "person";
  box.pose.orientation.w = 1.0;
  box.dimensions.x = box.dimensions.y = box.dimensions.z = 1.0;
  std::string why;
  ASSERT_EQ(wp::checkBox(wp::observe(box), wp::BoxLimits(), &why), wp::Drop::kCount) << why;
  box.position_error = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(wp::checkBox(wp::observe(box), wp::BoxLimits(), &why), wp::Drop::kNonFinite);
  EXPECT_NE(why.find("position_error"), std::string::npos) << why;
  box.position_error = -0.1;
  EXPECT_EQ(wp::checkBox(wp::observe(box), wp::BoxLimits(), &why), wp::Drop::kPosition);
  EXPECT_NE(why.find("position_error"), std::string::npos) << why;
  box.position_error = 0.0;
  box.velocity_error = -1.0;
  EXPECT_EQ(wp::checkBox(wp::observe(box), wp::BoxLimits(), &why), wp::Drop::kSpeed);
  EXPECT_NE(why.find("velocity_error"), std::string::npos) << why;
  box.velocity_error = std::numeric_limits<double>::infinity();
  EXPECT_EQ(wp::checkBox(wp::observe(box), wp::BoxLimits(), &why), wp::Drop::kNonFinite);
  EXPECT_NE(why.find("velocity_error"), std::string::npos) << why;
}

TEST(Conversions, StampsRoundTripToTheNanosecond) {
  for (const ros::Time t : {ros::Time(0, 0), ros::Time(1, 1), ros::Time(1763891234, 999999999)}) {
    EXPECT_EQ(wp::toTime(wp::toStamp(t)), t);
  }
  EXPECT_EQ(wp::toStamp(ros::Time(2, 5)), 2000000005);
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
  const wp::ContactEvent msg = wp::toMsg(e, a, b, wp::Level::kWarning);
  EXPECT_EQ(msg.id_a, "arm");
  EXPECT_EQ(msg.label_b, "person");
  EXPECT_EQ(msg.state, wp::ContactEvent::ONGOING);
  EXPECT_EQ(msg.level, wp::ContactEvent::WARNING);
  const wp::PairEvent back = wp::fromMsg(msg);
  // Every field comes back unchanged.
  EXPECT_EQ(std::tie(back.state, back.time_to_contact, back.time_to_separation, back.distance,
                     back.closing_speed),
            std::tie(e.state, e.time_to_contact, e.time_to_separation, e.distance, e.closing_speed));
  EXPECT_EQ(std::tie(back.point_a, back.point_b, back.normal), std::tie(e.point_a, e.point_b, e.normal));
}

TEST(Conversions, ContactsMessageCarriesTheReport) {
  // Two unit cubes 2 m apart closing at 1 m/s: one BEGIN at t = 2 s (analytic).
  wp::ProximityWorld world;
  wp::BodyMotion ma, mb;
  mb.position = {3, 0, 0};
  mb.linear_velocity = {-1, 0, 0};
  const wp::BodyHandle a = world.addBody({"a", "robot", wp::BodyGroup::kRobot, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, ma);
  const wp::BodyHandle b = world.addBody({"b", "person", wp::BodyGroup::kObject, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, mb);
  const std::vector<wp::PairEvent>& events = world.predict(5.0);
  ASSERT_EQ(events.size(), 1u);
  wp::CycleReport report;
  report.stamp = 7000000001;
  report.events = &events;
  report.levels = {wp::Level::kCritical};
  report.stale = {1};
  report.degraded = true;
  report.status_lines = {"source /x: no data yet"};
  wp::ContactEventArray msg;
  wp::fillContacts(report, world, "map", &msg);
  EXPECT_EQ(msg.header.stamp, ros::Time(7, 1));
  EXPECT_EQ(msg.header.frame_id, "map");
  ASSERT_EQ(msg.events.size(), 1u);
  EXPECT_EQ(msg.events[0].state, wp::ContactEvent::BEGIN);
  EXPECT_EQ(msg.events[0].id_a, world.desc(a).id);
  EXPECT_EQ(msg.events[0].id_b, world.desc(b).id);
  EXPECT_NEAR(msg.events[0].time_to_contact, 2.0, 1e-9);
  EXPECT_EQ(msg.events[0].level, wp::ContactEvent::CRITICAL);
  EXPECT_TRUE(msg.events[0].stale);
  EXPECT_EQ(msg.status, wp::ContactEventArray::DEGRADED);
  EXPECT_EQ(msg.status_details, report.status_lines);

  // A report without events (a failed cycle) empties the message but keeps it DEGRADED.
  report.events = nullptr;
  report.status_lines = {"cycle failed: boom"};
  wp::fillContacts(report, world, "map", &msg);
  EXPECT_TRUE(msg.events.empty());
  EXPECT_EQ(msg.status, wp::ContactEventArray::DEGRADED);
}

TEST(Conversions, SafetyStatusCarriesTheVerdict) {
  wp::ProximityWorld world;
  const wp::BodyHandle r = world.addBody(
      {"tool", "robot", wp::BodyGroup::kRobot, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, wp::BodyMotion());
  const wp::BodyHandle o = world.addBody(
      {"person_1", "person", wp::BodyGroup::kObject, wp::Shape::box({0.5, 0.5, 0.5}), 0.0}, wp::BodyMotion());
  wp::CycleReport report;
  report.stamp = 3000000002;
  report.ssm.enabled = true;
  report.ssm.speed_scale = 0.375;
  report.ssm.raw_scale = 0.5;
  report.ssm.limited = true;
  report.ssm.robot = r;
  report.ssm.object = o;
  report.ssm.separation = 0.75;
  report.ssm.required_separation = 0.87;
  report.ssm.approach_speed = 1.0;
  report.ssm.reason = "person_1 at 0.75 m from tool";
  wp::SafetyStatus msg;
  wp::fillSafetyStatus(report, world, "map", &msg);
  EXPECT_EQ(msg.header.stamp, ros::Time(3, 2));
  EXPECT_EQ(msg.header.frame_id, "map");
  EXPECT_EQ(msg.speed_scale, 0.375);
  EXPECT_EQ(msg.raw_scale, 0.5);
  EXPECT_FALSE(msg.protective_stop);
  EXPECT_EQ(msg.id_robot, "tool");
  EXPECT_EQ(msg.id_object, "person_1");
  EXPECT_EQ(msg.separation, 0.75);
  EXPECT_EQ(msg.required_separation, 0.87);
  EXPECT_EQ(msg.approach_speed, 1.0);
  EXPECT_EQ(msg.status, wp::SafetyStatus::OK);
  EXPECT_EQ(msg.reason, report.ssm.reason);
  // No pair within reach, DEGRADED, stopped.
  report.ssm.limited = false;
  report.ssm.speed_scale = 0.0;
  report.ssm.separation = std::numeric_limits<double>::infinity();
  report.degraded = true;
  wp::fillSafetyStatus(report, world, "map", &msg);
  EXPECT_TRUE(msg.protective_stop);
  EXPECT_TRUE(msg.id_robot.empty());
  EXPECT_TRUE(msg.id_object.empty());
  EXPECT_TRUE(std::isinf(msg.separation));
  EXPECT_EQ(msg.status, wp::SafetyStatus::DEGRADED);
}

TEST(Conversions, SpeedOverrideIsThePercentRounded) {
  EXPECT_EQ(wp::speedOverride(0.0), 0);
  EXPECT_EQ(wp::speedOverride(1.0), 100);
  EXPECT_EQ(wp::speedOverride(0.374), 37);
  EXPECT_EQ(wp::speedOverride(0.375), 38);  // half away from zero
  EXPECT_EQ(wp::speedOverride(0.999), 100);
  EXPECT_EQ(wp::speedOverride(0.004), 0);
  EXPECT_EQ(wp::speedOverride(-0.5), 0);
  EXPECT_EQ(wp::speedOverride(3.0), 100);
}

TEST(Conversions, TwistIsScaledOrZeroedWhenStale) {
  geometry_msgs::Twist in;
  in.linear.x = 1.0;
  in.linear.y = -2.0;
  in.linear.z = 0.5;
  in.angular.x = 0.1;
  in.angular.y = -0.2;
  in.angular.z = 0.4;
  const geometry_msgs::Twist half = wp::scaledTwist(in, 0.5, false);
  EXPECT_EQ(half.linear.x, 0.5);
  EXPECT_EQ(half.linear.y, -1.0);
  EXPECT_EQ(half.linear.z, 0.25);
  EXPECT_EQ(half.angular.x, 0.05);
  EXPECT_EQ(half.angular.y, -0.1);
  EXPECT_EQ(half.angular.z, 0.2);
  const geometry_msgs::Twist stale = wp::scaledTwist(in, 0.5, true);
  EXPECT_EQ(stale.linear.x, 0.0);
  EXPECT_EQ(stale.linear.y, 0.0);
  EXPECT_EQ(stale.angular.z, 0.0);
}

TEST(Reconfigure, ConfigAndParametersRoundTrip) {
  wp::MonitorParams p;
  p.horizon = 3.5;
  p.rate = 20.0;
  p.labels["default"] = wp::LabelSettings{0.15, 1.2, 0.3, 0.6, 0.1};
  p.labels["forklift"] = wp::LabelSettings{0.3, 2.0, 1.0, 1.0, 0.5};
  p.robot_thresholds.warning_time = 0.8;
  p.marker_rate = 5.0;
  const wp::ProximityMonitorConfig c = wp::toConfig(p);
  EXPECT_EQ(c.horizon, 3.5);
  EXPECT_EQ(c.default_margin, 0.15);
  EXPECT_EQ(c.person_margin, 0.15);  // person not configured: shows the default's values
  EXPECT_EQ(c.robot_warning_time, 0.8);
  const wp::MonitorParams back = wp::applyConfig(p, c);
  EXPECT_EQ(back.labels.count("person"), 0u);  // not created by a round trip
  EXPECT_EQ(back.labels.at("forklift").warning_time, 2.0);  // labels not in the config stay
  EXPECT_EQ(back.horizon, 3.5);
  EXPECT_EQ(back.rate, 20.0);
  EXPECT_EQ(back.marker_rate, 5.0);
  EXPECT_EQ(back.robot_thresholds.warning_time, 0.8);

  wp::ProximityMonitorConfig person = c;
  person.person_warning_time = 3.0;
  EXPECT_EQ(wp::applyConfig(p, person).label("person").warning_time, 3.0);

  // Speed and separation monitoring: every constant, and the labels' minimum speeds.
  wp::MonitorParams s = p;
  s.ssm.reaction_time = 0.05;
  s.ssm.stopping_time = 0.4;
  s.ssm.intrusion_distance = 0.2;
  s.ssm.sensor_uncertainty = 0.15;
  s.ssm.robot_uncertainty = 0.03;
  s.ssm.robot_max_speed = 1.5;
  s.ssm.max_increase_rate = 0.25;
  s.ssm.hold_time = 1.0;
  s.ssm.degraded_scale = 0.2;
  s.labels["default"].ssm_min_speed = 0.5;
  s.labels["person"] = s.labels["default"];
  s.labels["person"].ssm_min_speed = 1.6;
  const wp::ProximityMonitorConfig sc = wp::toConfig(s);
  EXPECT_EQ(sc.ssm_hold_time, 1.0);
  EXPECT_EQ(sc.person_ssm_min_speed, 1.6);
  const wp::MonitorParams sb = wp::applyConfig(wp::MonitorParams(), sc);
  EXPECT_EQ(sb.ssm.reaction_time, 0.05);
  EXPECT_EQ(sb.ssm.stopping_time, 0.4);
  EXPECT_EQ(sb.ssm.intrusion_distance, 0.2);
  EXPECT_EQ(sb.ssm.sensor_uncertainty, 0.15);
  EXPECT_EQ(sb.ssm.robot_uncertainty, 0.03);
  EXPECT_EQ(sb.ssm.robot_max_speed, 1.5);
  EXPECT_EQ(sb.ssm.max_increase_rate, 0.25);
  EXPECT_EQ(sb.ssm.hold_time, 1.0);
  EXPECT_EQ(sb.ssm.degraded_scale, 0.2);
  EXPECT_EQ(sb.label("default").ssm_min_speed, 0.5);
  EXPECT_EQ(sb.label("person").ssm_min_speed, 1.6);
}

TEST(Reconfigure, GrowthBoundsRoundTripAndSurviveOtherChanges) {
  wp::MonitorParams p;
  wp::LabelSettings person;
  person.position_error = 0.05;
  person.velocity_error = 0.3;
  person.max_accel = 4.0;
  person.max_speed = 2.0;
  p.labels["person"] = person;
  p.labels["default"].velocity_error = 0.1;
  const wp::ProximityMonitorConfig c = wp::toConfig(p);
  EXPECT_EQ(std::tie(c.person_position_error, c.person_velocity_error, c.person_max_accel,
                     c.person_max_speed),
            std::make_tuple(0.05, 0.3, 4.0, 2.0));
  EXPECT_EQ(std::tie(c.default_velocity_error, c.default_max_accel), std::make_tuple(0.1, 0.0));
  // Changing something else keeps every bound (the config carries them all).
  wp::ProximityMonitorConfig other = c;
  other.horizon = 4.0;
  other.person_warning_time = 2.0;
  const wp::MonitorParams back = wp::applyConfig(p, other);
  EXPECT_EQ(back.label("person").position_error, 0.05);
  EXPECT_EQ(back.label("person").velocity_error, 0.3);
  EXPECT_EQ(back.label("person").max_accel, 4.0);
  EXPECT_EQ(back.label("person").max_speed, 2.0);
  EXPECT_EQ(back.label("default").velocity_error, 0.1);
  // A tuned bound applies; a person entry differing from the default only in its bounds is
  // created.
  wp::MonitorParams plain;
  wp::ProximityMonitorConfig tuned = wp::toConfig(plain);
  tuned.person_max_accel = 3.0;
  const wp::MonitorParams t = wp::applyConfig(plain, tuned);
  ASSERT_EQ(t.labels.count("person"), 1u);
  EXPECT_EQ(t.labels.at("person").max_accel, 3.0);
  // A negative one is refused by name.
  tuned.person_max_accel = -1.0;
  wp::MonitorParams next;
  std::vector<std::string> errors;
  EXPECT_FALSE(wp::checkConfig(plain, tuned, &next, &errors));
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find("labels/person/max_accel"), std::string::npos) << errors[0];
}

TEST(Reconfigure, InvalidChangesAreRefusedWithTheReason) {
  const wp::MonitorParams p;
  wp::ProximityMonitorConfig c = wp::toConfig(p);
  c.person_critical_time = c.person_warning_time + 1.0;
  wp::MonitorParams next;
  next.horizon = 42.0;
  std::vector<std::string> errors;
  EXPECT_FALSE(wp::checkConfig(p, c, &next, &errors));
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors[0].find("labels/person/critical_time"), std::string::npos) << errors[0];
  EXPECT_EQ(next.horizon, 42.0);  // untouched
  c = wp::toConfig(p);
  c.stale_after = p.track_timeout + 1.0;
  EXPECT_FALSE(wp::checkConfig(p, c, &next, &errors));
  c = wp::toConfig(p);
  c.horizon = 7.0;
  EXPECT_TRUE(wp::checkConfig(p, c, &next, &errors));
  EXPECT_EQ(next.horizon, 7.0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
