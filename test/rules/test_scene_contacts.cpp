// The node's contact scenes, ROS-free (formerly the rostests head_on, near_miss, rotated_boxes,
// rotating_box, event_lifecycle and margins): the same scenes and checks against the same
// analytic answers, run through the Monitor in simulated time (test/shared/node_scene.hpp).
// Each test's comment names the rostest it replaces; the message wiring those rostests also
// exercised is covered by the rostests that remain (input_topics, robustness, markers, ...).

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "node_scene.hpp"      // test/shared

namespace wp = workspace_proximity;
using wp_test::SceneCycle;
using wp_test::SceneEvent;
using wp_test::SceneNode;
using wp_test::SceneTrack;

namespace {

const Eigen::Vector3d kCube(1, 1, 1);

SceneNode nodeWith(const wp::MonitorParams& p, std::vector<wp::RobotBodySpec> robot = {}) {
  return SceneNode(p, std::move(robot), {"/tracked_objects"}, false);
}

wp_test::ScenePublisher publisherOf(std::vector<SceneTrack>* tracks, double latency) {
  wp_test::ScenePublisher p;
  p.tracks = tracks;
  p.latency = latency;
  return p;
}

Eigen::Quaterniond yawed(double yaw) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
}

std::string sequence(const std::vector<SceneCycle>& cycles, const std::string& a,
                     const std::string& b) {
  std::string seq;
  for (const SceneCycle& c : cycles) seq += wp_test::stateChar(c.events, a, b);
  return seq;
}

}  // namespace

// head_on: two 1 m cubes 4 m apart closing at 2 m/s touch 2.0 s after t0, published with a
// 0.1 s latency; every event agrees with the analytic answer for its cycle's instant. The
// scene runs on into overlap, then stops being published: stale after ~stale_after (0.25 s),
// END when the tracks time out. OK while every input is fresh.
TEST(SceneContacts, HeadOnApproachIsAnalytic) {
  constexpr double kHorizon = 10.0;
  wp::MonitorParams p = wp_test::commonParams();
  p.horizon = kHorizon;
  SceneNode node = nodeWith(p);
  std::vector<SceneTrack> tracks{
      SceneTrack("a", "default", {-2.5, 0.3, 1.0}, kCube, {1.0, 0.0, 0.0}),
      SceneTrack("b", "default", {2.5, 0.3, 1.0}, kCube, {-1.0, 0.0, 0.0})};
  node.publishers.push_back(publisherOf(&tracks, 0.1));
  node.publishers[0].stop = 2.6;  // contact at 2.0, then 0.6 s of overlap
  const std::vector<SceneCycle> cycles = node.record(0.0, 2.6 + 1.2);
  const double last_stamp = node.publishers[0].last_stamp[0];
  ASSERT_GT(cycles.size(), 40u);
  const wp::LabelSettings& thresholds = p.label("default");
  const Eigen::Vector3d half(0.5, 0.5, 0.5);
  int approach = 0, overlap = 0, stale = 0;
  for (const SceneCycle& c : cycles) {
    const double age = c.t - last_stamp;
    if (c.t > 0.5 && age < 0.0) {
      EXPECT_FALSE(c.degraded) << c.t << " " << wp_test::joined(c.status_lines);
    }
    for (const SceneEvent& ev : c.events) {
      EXPECT_TRUE(ev.id_a == "a" && ev.id_b == "b") << "unexpected event " << describe(ev);
    }
    for (const SceneEvent* ev : wp_test::eventsFor(c.events, "a", "b")) {
      EXPECT_EQ(ev->label_a, "default");
      EXPECT_EQ(ev->label_b, "default");
      if (ev->state == wp::ContactState::kEnd) continue;
      if (age < -0.05) {
        EXPECT_FALSE(ev->stale) << "stale while published: " << describe(*ev);
      } else if (age > 0.26) {
        EXPECT_TRUE(ev->stale) << "not stale " << age << " s after the last stamp";
        ++stale;
      }
      const wp_test::AabbPrediction exp =
          wp_test::aabbPrediction(tracks[0].centre(c.t), half, tracks[0].velocity(c.t),
                                  tracks[1].centre(c.t), half, tracks[1].velocity(c.t), kHorizon);
      EXPECT_TRUE(exp.touches) << "event although no contact is possible at " << c.t;
      // The analytic contact: gap 4 m closing at 2 m/s from t0, separation at t0 + 3.
      EXPECT_NEAR(exp.ttc, std::max(0.0, 2.0 - c.t), 1e-9);
      EXPECT_NEAR(exp.tts, std::min(3.0 - c.t, kHorizon), 1e-9);
      wp_test::expectFaceContact(*ev, exp, tracks[0].centre(c.t), half, tracks[1].centre(c.t),
                                 half, "t=" + std::to_string(c.t));
      if (exp.distance > 0) {
        ++approach;
        EXPECT_NEAR(ev->normal.x(), 1.0, 1e-3);
        EXPECT_NEAR(ev->closing_speed, 2.0, 1e-3);
      } else {
        ++overlap;
        EXPECT_LE(ev->time_to_contact, wp_test::kTimeTol) << describe(*ev);
        EXPECT_LE(ev->distance, 1e-4) << describe(*ev);
      }
      bool decided = false;
      const wp::Level level = wp_test::expectedLevel(exp.ttc, exp.distance, thresholds, &decided);
      if (decided) {
        EXPECT_EQ(ev->level, level) << "level of " << describe(*ev);
      }
    }
  }
  EXPECT_GE(approach, 20);
  EXPECT_GE(overlap, 5);
  EXPECT_GE(stale, 2);
  const std::string seq = wp_test::shortened(sequence(cycles, "a", "b"));
  EXPECT_TRUE(seq == "BOE" || seq == ".BOE" || seq == "BOE." || seq == ".BOE.") << seq;
  for (const SceneCycle& c : cycles) {
    const auto evs = wp_test::eventsFor(c.events, "a", "b");
    if (evs.empty()) continue;
    EXPECT_EQ(evs[0]->state, wp::ContactState::kBegin);
    break;
  }
}

// near_miss: a 1 m cube moving along (1, -1, 0) at 1.41 m/s passes the vertical edge of a
// resting 1 m cube 0.035 m away at closest (t0 + 3.025 s): each axis overlaps for a while but
// never all at once, so no event. Positive control 50 m higher with 0.1 m label margins ("padded"):
// the inflated shapes overlap by 0.165 m, reported in nearly every cycle up to t0 + 3 s.
TEST(SceneContacts, ANearMissGivesNoEventAndItsPaddedTwinDoes) {
  wp::MonitorParams p = wp_test::commonParams();
  p.labels["padded"] = wp::LabelSettings{0.1, 1.0, 0.4, 0.5, 0.2};
  SceneNode node = nodeWith(p);
  std::vector<SceneTrack> tracks{
      SceneTrack("miss_a", "default", {0.0, 0.0, 0.0}, kCube),
      SceneTrack("miss_b", "default", {-2.0, 4.05, 0.0}, kCube, {1.0, -1.0, 0.0}),
      SceneTrack("ctl_a", "padded", {0.0, 0.0, 50.0}, kCube),
      SceneTrack("ctl_b", "padded", {-2.0, 4.05, 50.0}, kCube, {1.0, -1.0, 0.0})};
  node.publishers.push_back(publisherOf(&tracks, 0.05));
  const std::vector<SceneCycle> cycles = node.record(0.0, 3.6, 0.3);
  ASSERT_GT(cycles.size(), 40u);
  int control_cycles = 0, window = 0;
  for (const SceneCycle& c : cycles) {
    for (const SceneEvent& ev : c.events) {
      EXPECT_TRUE(ev.id_a == "ctl_a" && ev.id_b == "ctl_b")
          << "unexpected event at t=" << c.t << ": " << describe(ev);
    }
    if (c.t <= 3.0) {
      ++window;
      for (const SceneEvent* ev : wp_test::eventsFor(c.events, "ctl_a", "ctl_b")) {
        if (ev->state != wp::ContactState::kEnd) {
          ++control_cycles;
          break;
        }
      }
    }
  }
  EXPECT_GE(control_cycles, static_cast<int>(0.9 * window))
      << "positive control reported in only " << control_cycles << " of " << window;
}

// rotated_boxes: rotated boxes whose axis-aligned bounds overlap but which never touch (two
// parallel 45-degree sticks 0.3 m apart, one sliding along its axis; a cube and a -45-degree
// stick 0.15 m off its vertical edge, sliding along its axis): no event. Controls with the
// same geometry closing across the axis (0.1 and 0.05 m/s, touching at t0 + 3.0 s): analytic
// time to contact, distance, normal, closing speed and nearest points.
TEST(SceneContacts, RotatedBoxesWithOverlappingBoundsAreNotContacts) {
  constexpr double kHorizon = 5.0;
  const double s = 1.0 / std::sqrt(2.0);
  const Eigen::Vector3d u(s, s, 0.0), n(s, -s, 0.0);  // along and across the +45-degree sticks
  constexpr double kCubeGap = 0.15;
  const double c_off = s + 0.1 + kCubeGap;  // the -45-degree stick's centre from the cube's
  const Eigen::Vector3d stick(3.0, 0.2, 0.2);
  auto z = [](double h) { return Eigen::Vector3d(0.0, 0.0, h); };
  const Eigen::Quaterniond q45 = yawed(M_PI / 4), qm45 = yawed(-M_PI / 4);
  SceneNode node = nodeWith(wp_test::commonParams());
  std::vector<SceneTrack> tracks{
      SceneTrack("stick_a", "default", z(0), stick, Eigen::Vector3d::Zero(), q45),
      SceneTrack("stick_b", "default", 0.5 * n, stick, 0.5 * u, q45),
      SceneTrack("cube_c", "default", z(50), kCube),
      SceneTrack("stick_d", "default", c_off * u + z(50), stick, 0.5 * n, qm45),
      SceneTrack("ctl_a1", "default", z(100), stick, Eigen::Vector3d::Zero(), q45),
      SceneTrack("ctl_b1", "default", 0.5 * n + z(100), stick, -0.1 * n, q45),
      SceneTrack("ctl_cube", "default", z(150), kCube),
      SceneTrack("ctl_stick", "default", c_off * u + z(150), stick, -0.05 * u, qm45)};
  node.publishers.push_back(publisherOf(&tracks, 0.05));
  const std::vector<SceneCycle> cycles = node.record(0.0, 2.2, 0.3);
  ASSERT_GT(cycles.size(), 25u);
  // A control pair closing at `speed` along `normal` from `initial_gap`: never END, times,
  // distance, normal and speed analytic. Returns the gap now.
  auto closing = [&](const SceneEvent& ev, double t, double initial_gap, double speed,
                     const Eigen::Vector3d& normal) {
    EXPECT_NE(ev.state, wp::ContactState::kEnd) << describe(ev);
    const double gap = initial_gap - speed * t;
    EXPECT_NEAR(ev.time_to_contact, gap / speed, wp_test::kTimeTol) << t << " " << describe(ev);
    EXPECT_NEAR(ev.time_to_separation, kHorizon, wp_test::kTimeTol) << describe(ev);
    EXPECT_NEAR(ev.distance, gap, 1e-4) << describe(ev);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ev.normal[k], normal[k], 1e-3) << describe(ev);
    EXPECT_NEAR(ev.closing_speed, speed, 1e-3) << describe(ev);
    return gap;
  };
  int sticks = 0, cube = 0;
  for (const SceneCycle& c : cycles) {
    for (const SceneEvent& ev : c.events) {
      const std::pair<std::string, std::string> pair(ev.id_a, ev.id_b);
      EXPECT_TRUE(pair == std::make_pair(std::string("ctl_a1"), std::string("ctl_b1")) ||
                  pair == std::make_pair(std::string("ctl_cube"), std::string("ctl_stick")))
          << "unexpected event at t=" << c.t << ": " << describe(ev);
    }
    if (c.t > 2.0) continue;
    for (const SceneEvent* ev : wp_test::eventsFor(c.events, "ctl_a1", "ctl_b1")) {
      const double gap = closing(*ev, c.t, 0.3, 0.1, n);
      EXPECT_NEAR(ev->point_a.dot(n), 0.1, 1e-4) << describe(*ev);
      EXPECT_NEAR(ev->point_b.dot(n), 0.1 + gap, 1e-4) << describe(*ev);
      ++sticks;
    }
    for (const SceneEvent* ev : wp_test::eventsFor(c.events, "ctl_cube", "ctl_stick")) {
      const double gap = closing(*ev, c.t, kCubeGap, 0.05, u);
      // The cube's nearest point lies on its vertical edge x = y = 0.5.
      EXPECT_NEAR(ev->point_a.x(), 0.5, 1e-4) << describe(*ev);
      EXPECT_NEAR(ev->point_a.y(), 0.5, 1e-4) << describe(*ev);
      EXPECT_NEAR(ev->point_b.dot(u), s + gap, 1e-4) << describe(*ev);
      ++cube;
    }
  }
  EXPECT_GE(sticks, 20);
  EXPECT_GE(cube, 20);
}

// rotating_box: a stick (2 x 0.1 x 0.1 m) turns about z at 0.5 rad/s from yaw -1 rad towards a
// wall whose face is at x = 0.95; its farthest corner reaches x = cos(yaw) + 0.05 |sin(yaw)|,
// 0.95 at yaw -0.371 (contact) and +0.371 (separation). Published with a 0.1 s latency and the
// orientation of their stamp, so the monitor extrapolates the orientation with the angular
// twist. Every event against the exact values at its cycle's instant.
TEST(SceneContacts, ARotatingBoxMeetsTheWallWhenItsCornerDoes) {
  constexpr double kHorizon = 5.0, kHalfL = 1.0, kHalfW = 0.05, kFace = 0.95;
  constexpr double kYaw0 = -1.0, kRate = 0.5;
  auto reach = [&](double yaw) {
    return kHalfL * std::abs(std::cos(yaw)) + kHalfW * std::abs(std::sin(yaw));
  };
  auto bisect = [&](double lo, double hi) {
    auto f = [&](double y) { return reach(y) - kFace; };
    double flo = f(lo);
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      if ((f(mid) > 0) == (flo > 0)) {
        lo = mid;
        flo = f(mid);
      } else {
        hi = mid;
      }
    }
    return 0.5 * (lo + hi);
  };
  const double yaw_contact = bisect(-1.2, -0.06), yaw_separate = bisect(0.06, 1.2);
  EXPECT_NEAR(yaw_contact, -0.371, 2e-3);
  SceneNode node = nodeWith(wp_test::commonParams());
  std::vector<SceneTrack> tracks{
      SceneTrack::turning("stick", "default", {0.0, 0.0, 0.0}, {2 * kHalfL, 2 * kHalfW, 0.1},
                          kYaw0, kRate),
      SceneTrack("wall", "default", {kFace + 0.5, 0.0, 0.0}, {1.0, 3.0, 1.0})};
  node.publishers.push_back(publisherOf(&tracks, 0.1));
  const std::vector<SceneCycle> cycles = node.record(0.0, 2.0, 0.3);
  int approach = 0, overlap = 0;
  for (const SceneCycle& c : cycles) {
    if (c.t > 1.95) break;
    const double yaw = kYaw0 + kRate * c.t;
    const double ttc = std::max(0.0, (yaw_contact - yaw) / kRate);
    const double tts = std::min((yaw_separate - yaw) / kRate, kHorizon);
    std::vector<const SceneEvent*> evs;
    for (const SceneEvent* e : wp_test::eventsFor(c.events, "stick", "wall")) {
      if (e->state != wp::ContactState::kEnd) evs.push_back(e);
    }
    ASSERT_EQ(evs.size(), 1u) << "t=" << c.t;
    const SceneEvent& ev = *evs[0];
    EXPECT_NEAR(ev.time_to_contact, ttc, wp_test::kTimeTol) << "ttc t=" << c.t << " " << describe(ev);
    EXPECT_NEAR(ev.time_to_separation, tts, wp_test::kTimeTol) << "tts " << describe(ev);
    if (ttc > 0) {
      ++approach;
      // The farthest corner: local (half length, half width) for yaw < 0.
      const double cx = kHalfL * std::cos(yaw) - kHalfW * std::sin(yaw);
      const double cy = kHalfL * std::sin(yaw) + kHalfW * std::cos(yaw);
      EXPECT_NEAR(ev.distance, kFace - cx, 1e-4) << "distance " << describe(ev);
      EXPECT_NEAR(ev.normal.x(), 1.0, 1e-3) << "normal " << describe(ev);
      EXPECT_NEAR(ev.closing_speed, -kRate * cy, 1e-3) << "closing_speed " << describe(ev);
      EXPECT_NEAR(ev.point_a.x(), cx, 1e-4) << describe(ev);
      EXPECT_NEAR(ev.point_a.y(), cy, 1e-4) << describe(ev);
      EXPECT_NEAR(ev.point_b.x(), kFace, 1e-4) << describe(ev);
      EXPECT_NEAR(ev.point_b.y(), cy, 1e-4) << describe(ev);
    } else {
      ++overlap;
      EXPECT_LE(ev.distance, 1e-6) << describe(ev);
    }
  }
  EXPECT_GE(approach, 12);
  EXPECT_GE(overlap, 5);
}

// event_lifecycle: BEGIN -> ONGOING -> END -> BEGIN -> ONGOING -> END, horizon 2 s, boxes
// published in a frame "tracker" at (10, 0, 0) yawed 90 degrees from the fixed frame (tracker
// x is world y). box_a rests at the tracker's origin; box_b starts 3 m away and moves towards
// it at 1 m/s (entering the horizon at t0 + 1.0), away from t0 + 1.8, towards it at 2 m/s
// from t0 + 2.5 (BEGIN again at once), then is no longer published (END). Every cycle away
// from the switches against the exact prediction in world coordinates.
TEST(SceneContacts, EventsBeginGoOnEndAndBeginAgain) {
  constexpr double kHorizon = 2.0;
  wp::MonitorParams p = wp_test::commonParams();
  p.horizon = kHorizon;
  SceneNode node = nodeWith(p);
  std::vector<SceneTrack> tracks{
      SceneTrack("box_a", "default", {0.0, 0.0, 0.0}, kCube),
      SceneTrack("box_b", "default", {-4.0, 0.0, 0.0}, kCube, {1.0, 0.0, 0.0})};
  wp_test::ScenePublisher pub = publisherOf(&tracks, 0.05);
  Eigen::Isometry3d tracker = Eigen::Isometry3d::Identity();
  tracker.translate(Eigen::Vector3d(10.0, 0.0, 0.0));
  tracker.rotate(yawed(M_PI / 2));
  pub.frame = tracker;
  pub.stop = 3.0;
  node.publishers.push_back(pub);
  const std::vector<SceneCycle> cycles = node.record(0.0, 3.0 + 1.2, 0.2, [&](double t) {
    if (std::lround(t * 1000) == 1810) tracks[1].setVelocity(1.8, {-1.0, 0.0, 0.0});
    if (std::lround(t * 1000) == 2510) tracks[1].setVelocity(2.5, {2.0, 0.0, 0.0});
  });
  // The tracks in world coordinates: rotated a quarter turn (x, y) -> (-y, x), then shifted.
  std::vector<wp_test::CheckedBody> world;
  for (const SceneTrack& t : tracks) {
    world.push_back({t.id, t.label, Eigen::Vector3d(t.half().y(), t.half().x(), t.half().z()),
                     [&t, tracker](double s) { return Eigen::Vector3d(tracker * t.centre(s)); },
                     [&t, tracker](double s) { return Eigen::Vector3d(tracker.linear() * t.velocity(s)); }});
  }
  int checked = 0;
  for (const SceneCycle& c : cycles) {
    bool near_switch = false;
    for (double s : {1.8, 2.5}) near_switch |= s - 0.02 <= c.t && c.t <= s + 0.25;
    if (c.t <= 3.0 && !near_switch) checked += wp_test::expectSceneEvents(c.t, c.events, world, kHorizon);
  }
  EXPECT_GE(checked, 15);
  const std::string seq = wp_test::shortened(sequence(cycles, "box_a", "box_b"));
  EXPECT_TRUE(seq == ".BOE.BOE" || seq == ".BOE.BOE.") << seq;
  for (const SceneCycle& c : cycles) {
    const auto evs = wp_test::eventsFor(c.events, "box_a", "box_b");
    if (evs.empty()) continue;
    EXPECT_EQ(evs[0]->state, wp::ContactState::kBegin);
    // When the time to contact reaches the 2 s horizon at t0 + 1.0 s.
    EXPECT_TRUE(0.94 <= c.t && c.t <= 1.12) << "first BEGIN at t0 + " << c.t;
    break;
  }
}

// margins: label margins (default 0.1, person 0.2, forklift 0.3 m; an unknown label reads as
// default) and robot_margin (0.05 m) inflate the shapes, and the inflated shapes are what
// touch. Every pair approaches face-on: the exact numbers are those of boxes grown by the
// margins. Levels follow the stricter label's thresholds (robot_thresholds for the pillar).
TEST(SceneContacts, MarginsInflateTheShapesThatTouch) {
  constexpr double kHorizon = 5.0;
  wp::MonitorParams p = wp_test::commonParams();
  p.robot_margin = 0.05;
  p.labels["default"] = wp::LabelSettings{0.10, 1.0, 0.4, 0.5, 0.2};
  p.labels["person"] = wp::LabelSettings{0.20, 1.5, 0.6, 0.8, 0.3};
  p.labels["forklift"] = wp::LabelSettings{0.30, 2.0, 1.0, 1.0, 0.5};
  SceneNode node = nodeWith(p, {wp_test::robotBox("pillar", {0.2, 0.2, 1.0}, {0.0, 0.0, 1.0})});
  std::vector<SceneTrack> tracks{
      SceneTrack("walker", "person", {-2.45, 0.0, 1.0}, {0.5, 0.5, 0.5}, {0.5, 0.0, 0.0}),
      SceneTrack("cart", "forklift", {10.0, 0.0, 0.5}, kCube),
      SceneTrack("box", "default", {13.0, 0.0, 0.5}, kCube, {-1.0, 0.0, 0.0}),
      SceneTrack("alien_a", "alien", {20.0, 0.0, 0.5}, kCube),
      SceneTrack("alien_b", "alien", {22.5, 0.0, 0.5}, kCube, {-1.0, 0.0, 0.0})};
  node.publishers.push_back(publisherOf(&tracks, 0.05));
  const std::vector<SceneCycle> cycles = node.record(0.0, 1.4, 0.3);
  wp::LabelSettings robot = p.robot_thresholds;
  robot.margin = p.robot_margin;
  auto thresholds = [&](const std::string& label) -> const wp::LabelSettings& {
    return label == "robot" ? robot : p.label(label);
  };
  std::vector<wp_test::CheckedBody> bodies{wp_test::checkedStatic(
      "pillar", {0.0, 0.0, 1.0}, Eigen::Vector3d(0.2, 0.2, 1.0) + Eigen::Vector3d::Constant(0.05))};
  for (const SceneTrack& t : tracks) bodies.push_back(wp_test::checkedTrack(t, p.label(t.label).margin));
  int checked = 0;
  std::set<std::pair<std::string, std::string>> seen;
  for (const SceneCycle& c : cycles) {
    if (c.t > 1.25) break;
    checked += wp_test::expectSceneEvents(c.t, c.events, bodies, kHorizon, 5e-3, thresholds, false);
    for (const SceneEvent& ev : c.events) seen.insert({ev.id_a, ev.id_b});
  }
  const std::set<std::pair<std::string, std::string>> want{
      {"pillar", "walker"}, {"box", "cart"}, {"alien_a", "alien_b"}};
  EXPECT_EQ(seen, want);
  EXPECT_GE(checked, 40);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
