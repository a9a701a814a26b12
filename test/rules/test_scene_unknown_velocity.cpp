// A track whose velocity is not known yet (issues 23 and 24, "honest bounds"), as a scene in
// simulated time through the Monitor (test/shared/node_scene.hpp): a 0.5 m cube of label
// `unknown` (v_max 2 m/s, ssm_min_speed 1.6 m/s) walks at a robot post, drifting sideways and
// pausing, published every 50 ms (latency 50 ms) with velocity_known false. Checked every cycle
// against two oracles that do not use the monitor's growth code:
// - the same object, as last observed, running at v_max straight at the post (aabbPrediction,
//   the closed-form time of two boxes at constant velocity): the unknown track's
//   time_to_contact is never later, and no earlier either (growing at v_max from the stamp is
//   that motion's bound);
// - the object's true motion (its piecewise path, stepped at 1 ms): never later.
// And speed and separation take 1.6 m/s as its approach speed, whatever it is reported to do.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "node_scene.hpp"      // test/shared

namespace wp = workspace_proximity;
using wp_test::SceneEvent;
using wp_test::SceneNode;
using wp_test::SceneTrack;

namespace {

constexpr double kVmax = 2.0;  // m/s, the label's max_speed
const Eigen::Vector3d kPostCentre(0.0, 0.0, 1.0);
const Eigen::Vector3d kPostHalf(0.2, 0.2, 1.0);
const Eigen::Vector3d kCube(0.5, 0.5, 0.5);

wp::MonitorParams sceneParams() {
  wp::MonitorParams p = wp_test::commonParams();
  p.horizon = 2.0;  // the start (gap 4.55 m) is beyond v_max x horizon: not yet reported
  wp::LabelSettings unknown = p.labels["default"];  // margin 0: exact analytic times
  unknown.max_speed = kVmax;
  unknown.velocity_error = 0.3;  // ignored while the velocity is unknown
  unknown.max_accel = 4.0;
  unknown.ssm_min_speed = 1.6;
  p.labels["unknown"] = unknown;
  return p;
}

// The first instant in [0, horizon] at which the true object (its path from now on) touches
// the post, stepped at 1 ms; +infinity when it does not.
double trueFirstContact(const SceneTrack& track, double now, double horizon) {
  for (double tau = 0.0; tau <= horizon; tau += 1e-3) {
    const Eigen::Vector3d gap = (track.centre(now + tau) - kPostCentre).cwiseAbs() -
                                track.half() - kPostHalf;
    if (gap.maxCoeff() <= 0.0) return tau;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

TEST(SceneUnknownVelocity, NeverPredictedLaterThanTheSameObjectAtMaxSpeed) {
  const wp::MonitorParams p = sceneParams();
  SceneNode node(p, {wp_test::robotBox("post", kPostHalf, kPostCentre)}, {"/tracked_objects"},
                 false);
  // From x = -5 at 0.8 m/s towards the post, drifting along y (within the post's width, so
  // the gap is along x); standing from 2.5 s to 3.5 s; then 1.2 m/s again.
  std::vector<SceneTrack> tracks{
      SceneTrack("u", "unknown", {-5.0, -0.2, 1.0}, kCube, {0.8, 0.1, 0.0})};
  tracks[0].setVelocity(2.5, {0.0, 0.0, 0.0});
  tracks[0].setVelocity(3.5, {1.2, 0.05, 0.0});
  tracks[0].velocity_known = false;
  wp_test::ScenePublisher pub;
  pub.tracks = &tracks;
  pub.latency = 0.05;
  node.publishers.push_back(pub);

  int checked = 0, unreported = 0, ssm_checked = 0;
  node.run(0.0, 5.5, [&](double t, const wp::CycleReport& r) {
    const std::vector<double>& stamps = node.publishers[0].stamps;
    if (stamps.empty()) return;
    const double stamp = stamps.back();
    const Eigen::Vector3d seen = tracks[0].centre(stamp);
    // The same object as last observed, running at v_max straight at the post (along +x),
    // where it would be now.
    const Eigen::Vector3d running = seen + Eigen::Vector3d(kVmax, 0, 0) * (t - stamp);
    const wp_test::AabbPrediction at_max =
        wp_test::aabbPrediction(running, tracks[0].half(), {kVmax, 0, 0}, kPostCentre, kPostHalf,
                                Eigen::Vector3d::Zero(), p.horizon);
    const double truth = trueFirstContact(tracks[0], t, p.horizon);
    const SceneEvent* event = nullptr;
    const std::vector<SceneEvent> events = wp_test::sceneEvents(node.monitor, r);
    for (const SceneEvent* e : wp_test::eventsFor(events, "post", "u")) {
      if (e->state != wp::ContactState::kEnd) event = e;
    }
    if (at_max.touches) {
      ASSERT_NE(event, nullptr) << "t=" << t << ": no event, at v_max it touches in "
                                << at_max.ttc << " s";
      EXPECT_LE(event->time_to_contact, at_max.ttc + wp_test::kTimeTol)
          << "t=" << t << " " << wp_test::describe(*event);
      EXPECT_GE(event->time_to_contact, at_max.ttc - wp_test::kTimeTol)
          << "t=" << t << " " << wp_test::describe(*event);
      ++checked;
    } else {
      ++unreported;
    }
    if (event != nullptr) {
      EXPECT_LE(event->time_to_contact, truth + wp_test::kTimeTol)
          << "t=" << t << " later than the true motion: " << wp_test::describe(*event);
    }
    EXPECT_FALSE(std::isfinite(truth) && truth <= p.horizon && event == nullptr)
        << "t=" << t << ": the object touches in " << truth << " s, no event";
    // Speed and separation: the label's minimum, never the (unknown) reported velocity.
    if (r.ssm.limited) {
      EXPECT_NEAR(r.ssm.approach_speed, 1.6, 1e-12) << "t=" << t;
      ++ssm_checked;
    }
  });
  EXPECT_GT(checked, 60);    // from about 0.3 s on, within v_max x horizon
  EXPECT_GT(unreported, 2);  // before it, not
  EXPECT_GT(ssm_checked, 10);
}

// A label that states no max_speed says nothing about how fast its objects move: a track of it
// whose velocity is unknown has no stated motion model to be conservative against, so the cycle
// is DEGRADED, by name, for as long as such a track lives (and not because of a label that has
// a max_speed, or a track whose velocity is known).
TEST(SceneUnknownVelocity, DegradedWhileALabelWithoutMaxSpeedHasAnUnknownVelocity) {
  wp::MonitorParams p = sceneParams();
  wp::LabelSettings truck = p.labels["default"];
  truck.max_speed = 0.0;  // no cap stated
  p.labels["truck"] = truck;
  p.track_timeout = 0.5;
  SceneNode node(p, {wp_test::robotBox("post", kPostHalf, kPostCentre)}, {"/tracked_objects"},
                 false);
  std::vector<SceneTrack> tracks{
      SceneTrack("t1", "truck", {-5.0, 3.0, 1.0}, kCube, {0.5, 0.0, 0.0}),
      SceneTrack("t2", "truck", {-5.0, -3.0, 1.0}, kCube, {0.5, 0.0, 0.0}),
      SceneTrack("u", "unknown", {-5.0, 0.0, 1.0}, kCube, {0.5, 0.0, 0.0}),
      SceneTrack("k", "truck", {5.0, 0.0, 1.0}, kCube, {-0.5, 0.0, 0.0})};
  tracks[0].velocity_known = false;
  tracks[1].velocity_known = false;
  tracks[2].velocity_known = false;  // has max_speed: bounded, not a reason
  wp_test::ScenePublisher pub;
  pub.tracks = &tracks;
  pub.latency = 0.05;
  pub.stop = 2.0;  // then silent: the tracks time out (and the source is silent, another reason)
  node.publishers.push_back(pub);

  int degraded_by_truck = 0, lines_checked = 0, after = 0;
  node.run(0.0, 3.0, [&](double t, const wp::CycleReport& r) {
    if (node.publishers[0].stamps.empty()) return;
    int truck_lines = 0;
    for (const std::string& line : r.status_lines) {
      if (line.find("max_speed") == std::string::npos) continue;
      ++truck_lines;
      EXPECT_NE(line.find("label 'truck'"), std::string::npos) << line;
      EXPECT_NE(line.find("2 tracks"), std::string::npos) << line;
      EXPECT_EQ(line.find("'unknown'"), std::string::npos) << line;
      ++lines_checked;
    }
    EXPECT_TRUE(r.degraded) << "t=" << t;
    if (t <= 2.0) {
      EXPECT_EQ(truck_lines, 1) << "t=" << t;
      if (truck_lines == 1 && r.degraded) ++degraded_by_truck;
    } else if (t > 2.0 + p.track_timeout + 0.1) {
      EXPECT_EQ(truck_lines, 0) << "t=" << t << ": the tracks are gone";  // only while they live
      ++after;
    }
  });
  EXPECT_GT(degraded_by_truck, 20);
  EXPECT_GT(after, 5);
  EXPECT_GT(lines_checked, 20);
}

// The same label with every velocity known is not a reason.
TEST(SceneUnknownVelocity, LabelWithoutMaxSpeedIsFineWhileVelocitiesAreKnown) {
  wp::MonitorParams p = sceneParams();
  wp::LabelSettings truck = p.labels["default"];
  truck.max_speed = 0.0;
  p.labels["truck"] = truck;
  SceneNode node(p, {wp_test::robotBox("post", kPostHalf, kPostCentre)}, {"/tracked_objects"},
                 false);
  std::vector<SceneTrack> tracks{
      SceneTrack("t1", "truck", {-5.0, 3.0, 1.0}, kCube, {0.5, 0.0, 0.0})};
  wp_test::ScenePublisher pub;
  pub.tracks = &tracks;
  pub.latency = 0.05;
  node.publishers.push_back(pub);
  int checked = 0;
  node.run(0.0, 1.0, [&](double, const wp::CycleReport& r) {
    if (node.publishers[0].stamps.empty()) return;
    for (const std::string& line : r.status_lines) {
      EXPECT_EQ(line.find("max_speed"), std::string::npos) << line;
    }
    ++checked;
  });
  EXPECT_GT(checked, 10);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
