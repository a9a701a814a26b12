// The node's track scenes, ROS-free (formerly the rostests max_tracks, growth, empty_scene and
// the event part of track_timeout, whose marker part stays a rostest): the same scenes and
// checks against the same analytic answers, run through the Monitor in simulated time
// (test/shared/node_scene.hpp).

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <string>
#include <tuple>
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

wp_test::ScenePublisher publisherOf(std::vector<SceneTrack>* tracks, double latency,
                                    int source = 0) {
  wp_test::ScenePublisher p;
  p.tracks = tracks;
  p.latency = latency;
  p.source = source;
  return p;
}

bool mentions(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& l : lines) {
    if (l.find(text) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

// max_tracks = 2 ("beyond it the nearest to the robot win"), with two input topics. Robot body
// "post" (0.4 x 0.4 x 2 m at the origin). src_a publishes two boxes 30 m away from t0 - 0.6 s
// and fills the cap first; from t0 src_b publishes "near", a 0.5 m cube 1.8 m from the post
// approaching at 0.5 m/s (contact in 3.6 s). The nearest object must be monitored: the pair
// ("/src_b/near", "post") reported within 1 s, with its analytic time to contact.
TEST(SceneTracks, TheNearestTracksWinTheCap) {
  wp::MonitorParams p = wp_test::commonParams();
  p.max_tracks = 2;
  p.input_topics = {"src_a", "src_b"};
  SceneNode node(p, {wp_test::robotBox("post", {0.2, 0.2, 1.0}, {0.0, 0.0, 1.0})},
                 {"/src_a", "/src_b"}, true);
  std::vector<SceneTrack> far{SceneTrack("f1", "default", {30.0, 0.0, 1.0}, kCube),
                              SceneTrack("f2", "default", {-30.0, 0.0, 1.0}, kCube)};
  std::vector<SceneTrack> close{
      SceneTrack("near", "default", {-2.25, 0.0, 1.0}, {0.5, 0.5, 0.5}, {0.5, 0.0, 0.0})};
  node.publishers.push_back(publisherOf(&far, 0.05, 0));
  node.publishers.back().start = -0.6;
  node.publishers.push_back(publisherOf(&close, 0.05, 1));
  const std::vector<SceneCycle> cycles = node.record(-0.6, 2.0, 0.0);
  const std::string kNear = "/src_b/near";
  std::vector<std::pair<double, const SceneEvent*>> reported;
  for (const SceneCycle& c : cycles) {
    for (const SceneEvent* e : wp_test::eventsFor(c.events, kNear, "post")) {
      if (e->state != wp::ContactState::kEnd) reported.emplace_back(c.t, e);
    }
  }
  ASSERT_FALSE(reported.empty()) << "the nearest object was never monitored";
  EXPECT_LE(reported[0].first, 1.0) << "first reported " << reported[0].first << " s after it appeared";
  for (const auto& r : reported) {
    EXPECT_NEAR(r.second->time_to_contact, (1.8 - 0.5 * r.first) / 0.5, wp_test::kTimeTol)
        << "t=" << r.first << " " << describe(*r.second);
  }
}

// track_timeout (0.5 s, 20 Hz): "anchor" at rest, "far" at rest 20 m away, "mover" approaching
// the anchor at 1 m/s from 3 m (contact in 3 s). After 1.2 s the mover is no longer published.
// The pair (anchor, mover) is ONGOING until the mover is dropped, stale once its stamp is older
// than ~stale_after (0.25 s), END between 0.4 and 0.8 s after its last array, then nothing.
// (The markers' deletion is checked by the rostest track_timeout.)
TEST(SceneTracks, ATrackNoLongerPublishedGoesStaleThenEnds) {
  wp::MonitorParams p = wp_test::commonParams();
  p.track_timeout = 0.5;
  SceneNode node(p, {}, {"/tracked_objects"}, false);
  std::vector<SceneTrack> tracks{
      SceneTrack("anchor", "default", {0.0, 0.0, 0.0}, kCube),
      SceneTrack("mover", "default", {-4.0, 0.0, 0.0}, kCube, {1.0, 0.0, 0.0}),
      SceneTrack("far", "default", {20.0, 20.0, 0.0}, kCube)};
  node.publishers.push_back(publisherOf(&tracks, 0.0));
  const std::vector<SceneCycle> cycles = node.record(0.0, 1.2 + 2.0, 0.0, [&](double t) {
    if (std::lround(t * 1000) == 1200) tracks[1].active = false;
  });
  const double last_pub = node.publishers[0].last_stamp[1];  // latency 0: stamp = arrival
  std::string seq;
  for (const SceneCycle& c : cycles) seq += wp_test::stateChar(c.events, "anchor", "mover");
  seq = wp_test::shortened(seq);
  EXPECT_TRUE(seq == "BOE" || seq == ".BOE" || seq == "BOE." || seq == ".BOE.") << seq;
  const SceneCycle* end = nullptr;
  for (const SceneCycle& c : cycles) {
    for (const SceneEvent* e : wp_test::eventsFor(c.events, "anchor", "mover")) {
      if (e->state == wp::ContactState::kEnd && end == nullptr) end = &c;
    }
  }
  ASSERT_NE(end, nullptr);
  const double delay = end->t - last_pub;
  EXPECT_TRUE(0.4 <= delay && delay <= 0.8) << "END " << delay << " s after the last array";
  int stale_checked = 0;
  for (const SceneCycle& c : cycles) {
    const double age = c.t - last_pub;
    for (const SceneEvent* e : wp_test::eventsFor(c.events, "anchor", "mover")) {
      if (e->state == wp::ContactState::kEnd) continue;
      if (age < 0.15) {
        EXPECT_FALSE(e->stale) << "age " << age << ": " << describe(*e);
      } else if (age > 0.26) {
        EXPECT_TRUE(e->stale) << "age " << age << ": " << describe(*e);
        ++stale_checked;
      }
    }
  }
  EXPECT_GE(stale_checked, 2);
}

// growth: a static robot "pillar" (1 x 1 x 2 m, faces at x, y = +-0.5) and 1 m cubes standing
// around it, all margins 0. A label's growth R(s) = min(e s + a s^2 / 2, (v_max + |v|) s), s
// from the box's measurement stamp S, makes the grown cube touch the pillar at S + T with
// R(T) = face gap: p (person, e = 1.6 m/s, gap 1.6 m) T = 1.0 s; r (runner, a = 2 m/s^2, gap
// 1.0 m) T = 1.0 s; c (capped, a = 4, v_max = 1, gap 1.5 m) T = 1.5 s; s (default, gap 0.3 m)
// never; w (default, gap 2.5 m approaching at 1 m/s) at t0 + 2.5 s as before. The predicted
// instant must be S + T for one of the published stamps S (within 2 ms), never later, and the
// distance then gap - R(cycle - S).
TEST(SceneTracks, GrowingMarginsTouchWhenTheirGrowthReachesTheGap) {
  wp::MonitorParams p = wp_test::commonParams();
  // Object-object pairs are not this test's subject.
  p.ignore_pairs = {{"group:object", "group:object"}};
  wp::LabelSettings person = p.labels["default"], runner = person, capped = person;
  person.velocity_error = 1.6;
  runner.max_accel = 2.0;
  capped.max_accel = 4.0;
  capped.max_speed = 1.0;
  p.labels["person"] = person;
  p.labels["runner"] = runner;
  p.labels["capped"] = capped;
  ASSERT_TRUE(wp::validate(p).empty());
  SceneNode node(p, {wp_test::robotBox("pillar", {0.5, 0.5, 1.0}, {0.0, 0.0, 1.0})},
                 {"/tracked_objects"}, false);
  std::vector<SceneTrack> tracks{
      SceneTrack("p", "person", {0.5 + 1.6 + 0.5, 0.0, 1.0}, kCube),
      SceneTrack("r", "runner", {-(0.5 + 1.0 + 0.5), 0.0, 1.0}, kCube),
      SceneTrack("c", "capped", {0.0, 0.5 + 1.5 + 0.5, 1.0}, kCube),
      SceneTrack("s", "default", {0.0, -(0.5 + 0.3 + 0.5), 1.0}, kCube),
      SceneTrack("w", "default", {0.0, -(0.5 + 2.5 + 0.5), 1.0}, kCube, {0.0, 1.0, 0.0})};
  struct Standing {
    double t, gap, e, a, cap;  // cap 0: none
  };
  const std::map<std::string, Standing> standing{
      {"p", {1.0, 1.6, 1.6, 0.0, 0.0}}, {"r", {1.0, 1.0, 0.0, 2.0, 0.0}}, {"c", {1.5, 1.5, 0.0, 4.0, 1.0}}};
  auto growth = [](const Standing& g, double s) {
    const double r = g.e * s + 0.5 * g.a * s * s;
    return g.cap > 0 ? std::min(r, g.cap * s) : r;
  };
  node.publishers.push_back(publisherOf(&tracks, 0.05));
  node.publishers[0].stop = 1.2;
  const std::vector<SceneCycle> cycles = node.record(0.0, 1.2, 0.3);
  const std::vector<double>& stamps = node.publishers[0].stamps;
  ASSERT_GE(cycles.size(), 10u);
  std::map<std::string, int> checked{{"p", 0}, {"r", 0}, {"c", 0}, {"w", 0}};
  for (const SceneCycle& c : cycles) {
    if (c.t > 1.1) break;
    std::set<std::string> ids;
    for (const SceneEvent& ev : c.events) {
      EXPECT_TRUE(ev.id_a == "pillar" || ev.id_b == "pillar") << describe(ev);
      const std::string other = ev.id_a == "pillar" ? ev.id_b : ev.id_a;
      EXPECT_NE(ev.state, wp::ContactState::kEnd) << describe(ev);
      ids.insert(other);
      const double predicted = c.t + ev.time_to_contact;
      if (other == "w") {
        // Default settings: the constant-velocity contact at t0 + 2.5 s.
        EXPECT_NEAR(predicted, 2.5, 1e-3) << describe(ev);
        ++checked["w"];
        continue;
      }
      const auto it = standing.find(other);
      EXPECT_NE(it, standing.end()) << describe(ev);
      if (it == standing.end()) continue;
      const Standing& g = it->second;
      double used = stamps.front();
      for (double s : stamps) {
        if (std::abs(predicted - s - g.t) < std::abs(predicted - used - g.t)) used = s;
      }
      const double off = predicted - used - g.t;
      EXPECT_LE(std::abs(off), 2e-3) << describe(ev) << ": predicted " << predicted - used
                                     << " s after the nearest stamp, not " << g.t;
      EXPECT_LE(off, 1e-6) << "late: " << describe(ev);
      EXPECT_LE(used, c.t);
      EXPECT_NEAR(ev.distance, std::max(0.0, g.gap - growth(g, c.t - used)), 1e-4) << describe(ev);
      // The constant-velocity contact never comes (standing): separation = contact.
      EXPECT_EQ(ev.time_to_separation, ev.time_to_contact) << describe(ev);
      ++checked[other];
    }
    EXPECT_EQ(ids.count("s"), 0u) << "a standing box without growth must never be reached";
  }
  for (const auto& k : checked) EXPECT_GE(k.second, 8) << "too few events of " << k.first;
}

// empty_scene: with nothing to monitor every cycle still reports, empty ("silence never means
// all clear"): no events, no bodies, stamped with its cycle's instant (increasing), DEGRADED
// naming the source "tracked_objects" that never sent anything. (The node's timer rate, the
// arrays' frame and markers are the rostests marker_rate and markers'.)
TEST(SceneTracks, AnEmptySceneIsReportedEveryCycleAndNotClear) {
  wp::MonitorParams p = wp_test::commonParams();
  p.fixed_frame = "map";
  SceneNode node(p, {}, {"/tracked_objects"}, false);
  wp::Stamp prev = 0;
  int cycles = 0;
  node.run(0.0, 3.1, [&](double t, const wp::CycleReport& r) {
    ++cycles;
    EXPECT_EQ(r.eventCount(), 0u);
    EXPECT_TRUE(r.bodies.empty());
    EXPECT_EQ(r.stamp, wp_test::sceneStamp(t));
    EXPECT_GT(r.stamp, prev);
    prev = r.stamp;
    if (t > 1.1) {
      EXPECT_TRUE(r.degraded && mentions(r.status_lines, "tracked_objects"))
          << "expected DEGRADED naming the silent source: " << wp_test::joined(r.status_lines);
    }
  });
  EXPECT_GE(cycles, 30);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
