// The monitor's cycle, ROS-free: array stamps accepted or dropped by rule, latency-compensated
// analytic contacts, levels and stale flags per event, body levels, the OK / DEGRADED status
// and its reasons (silent or never-heard sources, unknown robot bodies, permanent issues,
// failed cycles), and the reset after a clock jump. Expected numbers are worked out by hand.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "workspace_proximity/rules/monitor.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kT0 = 1000 * kSecond;  // an arbitrary clock reading

bool mentions(const std::vector<std::string>& lines, const std::string& text) {
  for (const std::string& l : lines) {
    if (l.find(text) != std::string::npos) return true;
  }
  return false;
}

wp::MonitorParams params() {
  wp::MonitorParams p = wp_test::marginFreeParams(5.0, wp::LabelSettings{0.0, 2.5, 0.5, 0.1, 0.05});
  p.robot_thresholds = wp::LabelSettings{0.0, 1.0, 0.4, 0.1, 0.05};
  return p;
}

wp::RobotBodySpec post() { return wp_test::robotBox("post", {0.5, 0.5, 0.5}); }

struct Fixture {
  Fixture() : monitor(params(), {post()}, {"/boxes"}, false, nullptr), clock(&timing) {}
  // A person (1 m cube) at x, walking at v (m/s along x), observed at `stamp`.
  void person(double x, double v, wp::Stamp stamp, wp::Stamp now) {
    wp::BoxObservation b;
    b.id = "p1";
    b.label = "person";
    b.position = {x, 0, 0};
    b.dimensions = {1, 1, 1};
    b.linear_velocity = {v, 0, 0};
    monitor.noteReceipt(0, now);
    ASSERT_TRUE(monitor.ingest(0, stamp, now, Eigen::Isometry3d::Identity(), {b}));
  }
  void posePost() { ASSERT_TRUE(monitor.poseRobot(0, wp::BodyMotion())); }
  const wp::CycleReport& cycle(wp::Stamp now) { return monitor.cycle(now, &clock); }

  wp::Monitor monitor;
  wp::CycleTiming timing;
  wp::StageClock clock;
};

}  // namespace

TEST(MonitorCycle, AHeadOnApproachGivesTheAnalyticContactLatencyCompensated) {
  Fixture f;
  f.posePost();
  // Person's near face at 4.5 m, the post's at 0.5 m: gap 4 m at 2 m/s, observed 0.1 s before
  // the cycle, so 3.8 m at the cycle instant: contact 1.9 s ahead, separation when the person
  // has passed through (gap + 2 m of overlap) = 2.9 s.
  f.person(5.0, -2.0, kT0 - kSecond / 10, kT0 - kSecond / 20);
  const wp::CycleReport& r = f.cycle(kT0);
  ASSERT_EQ(r.eventCount(), 1u);
  const wp::PairEvent& e = r.event(0);
  EXPECT_EQ(e.state, wp::ContactState::kBegin);
  EXPECT_NEAR(e.time_to_contact, 1.9, 1e-6);
  EXPECT_NEAR(e.time_to_separation, 2.9, 1e-6);
  EXPECT_NEAR(e.distance, 3.8, 1e-9);
  EXPECT_EQ(r.stamp, kT0);
  // Person thresholds: warning at 2.5 s -> WARNING (the robot's 1.0 s alone would be NOTICE).
  EXPECT_EQ(r.levels[0], wp::Level::kWarning);
  EXPECT_EQ(r.stale[0], 0);
  EXPECT_EQ(r.bodyLevel(e.body_a.index), static_cast<int>(wp::Level::kWarning));
  EXPECT_EQ(r.bodyLevel(e.body_b.index), static_cast<int>(wp::Level::kWarning));
  EXPECT_EQ(r.bodies.size(), 2u);
  EXPECT_FALSE(r.degraded) << (r.status_lines.empty() ? "" : r.status_lines[0]);
  EXPECT_EQ(f.monitor.status().cycles, 1u);
}

TEST(MonitorCycle, AnOldTrackMakesItsPairsStale) {
  Fixture f;
  f.posePost();
  // stale_after 0.25 s: observed 0.3 s before the cycle (track_timeout 0.5 s keeps it).
  f.person(3.0, -1.0, kT0 - 3 * kSecond / 10, kT0);
  const wp::CycleReport& r = f.cycle(kT0);
  ASSERT_EQ(r.eventCount(), 1u);
  EXPECT_EQ(r.stale[0], 1);
}

TEST(MonitorCycle, StatusIsDegradedForEveryUnknownInputAndOkWhenAllIsFresh) {
  Fixture f;
  // Nothing heard, robot body never posed.
  const wp::CycleReport& r0 = f.cycle(kT0);
  EXPECT_TRUE(r0.degraded);
  EXPECT_TRUE(mentions(r0.status_lines, "source /boxes: no data yet"));
  EXPECT_TRUE(mentions(r0.status_lines, "robot body post unknown"));
  // Fresh data everywhere: OK.
  f.posePost();
  f.person(5.0, 0.0, kT0, kT0);
  EXPECT_FALSE(f.cycle(kT0 + kSecond / 10).degraded);
  // Silent for more than min(source_timeout 1.0, track_timeout 0.5) = 0.5 s: DEGRADED.
  f.posePost();
  const wp::CycleReport& r1 = f.cycle(kT0 + 6 * kSecond / 10);
  EXPECT_TRUE(r1.degraded);
  EXPECT_TRUE(mentions(r1.status_lines, "source /boxes: no data for 0.60 s"));
  // A robot body that cannot be posed: stale with its reason, its pairs stale.
  f.person(3.0, -1.0, kT0 + kSecond, kT0 + kSecond);
  f.monitor.markRobotUnknown(0, "no transform");
  const wp::CycleReport& r2 = f.cycle(kT0 + kSecond);
  EXPECT_TRUE(r2.degraded);
  EXPECT_TRUE(mentions(r2.status_lines, "robot body post stale: no transform"));
  ASSERT_EQ(r2.eventCount(), 1u);
  EXPECT_EQ(r2.stale[0], 1);
  // Kept where it was, without velocity.
  EXPECT_TRUE(f.monitor.world().motion(f.monitor.robot().handle(0)).linear_velocity.isZero());
}

TEST(MonitorCycle, ASilentSourceIsDegradedNoLaterThanItsTracksExpire) {
  // Tracks expire by their stamps, the source's silence counts from the arrays' arrival: with a
  // tracker latency of 0.1 s the person's track is gone 0.4 s after the last arrival, before
  // min(source_timeout, track_timeout) = 0.5 s of silence. That emptied scene must not be clear.
  Fixture f;
  f.posePost();
  f.person(5.0, 0.0, kT0 - kSecond / 10, kT0);
  EXPECT_FALSE(f.cycle(kT0 + kSecond / 10).degraded);
  f.posePost();
  const wp::CycleReport& r = f.cycle(kT0 + 45 * kSecond / 100);
  EXPECT_EQ(f.monitor.tracks().size(), 0);
  EXPECT_TRUE(r.degraded);
  EXPECT_TRUE(mentions(r.status_lines, "source /boxes: newest array stamped 0.55 s ago"))
      << (r.status_lines.empty() ? "" : r.status_lines[0]);
}

TEST(MonitorCycle, ASourceWhoseArraysAreAllDroppedIsAsUnknownAsASilentOne) {
  Fixture f;
  f.posePost();
  // Arrays keep arriving every 0.1 s, but each is dropped (its frame is unreachable, as the
  // input bridge reports it): DEGRADED naming the reason, not OK with an empty scene.
  for (int k = 0; k <= 10; ++k) {
    const wp::Stamp now = kT0 + k * kSecond / 10;
    f.monitor.noteReceipt(0, now);
    f.monitor.drop(wp::Drop::kFrame, 0, "cannot transform 'nowhere' to 'world'");
    f.posePost();
    const wp::CycleReport& r = f.cycle(now);
    EXPECT_TRUE(r.degraded) << k;
    EXPECT_TRUE(mentions(r.status_lines, "source /boxes: arrays arrive but none could be used yet "
                                         "(dropped: frame)")) << k;
  }
  // One usable array: OK. Then only boxes the checks refuse, for more than 0.5 s: DEGRADED.
  f.person(5.0, 0.0, kT0 + kSecond, kT0 + kSecond);
  f.posePost();
  EXPECT_FALSE(f.cycle(kT0 + kSecond).degraded);
  wp::BoxObservation bad;
  bad.id = "p1";
  bad.dimensions = {0, 1, 1};
  for (int k = 1; k <= 7; ++k) {
    const wp::Stamp now = kT0 + kSecond + k * kSecond / 10;
    f.monitor.noteReceipt(0, now);
    ASSERT_TRUE(f.monitor.ingest(0, now, now, Eigen::Isometry3d::Identity(), {bad}));
    f.posePost();
    const wp::CycleReport& r = f.cycle(now);
    const bool stale = k > 5;  // last used at 1.0 s; silent after 0.5 s
    EXPECT_EQ(r.degraded, stale) << k;
    if (stale) {
      EXPECT_TRUE(mentions(r.status_lines, "arrays arrive but none used for")) << k;
      EXPECT_TRUE(mentions(r.status_lines, "(dropped: dimensions)")) << k;
    }
  }
  // An empty array is data (nothing there): OK again.
  f.monitor.noteReceipt(0, kT0 + 2 * kSecond);
  ASSERT_TRUE(f.monitor.ingest(0, kT0 + 2 * kSecond, kT0 + 2 * kSecond,
                               Eigen::Isometry3d::Identity(), {}));
  f.posePost();
  EXPECT_FALSE(f.cycle(kT0 + 2 * kSecond).degraded);
}

TEST(MonitorCycle, APermanentIssueKeepsTheStatusDegraded) {
  Fixture f;
  f.monitor.addPermanentIssue("robot link arm: mesh cannot be read");
  f.posePost();
  f.person(5.0, 0.0, kT0, kT0);
  const wp::CycleReport& r = f.cycle(kT0);
  EXPECT_TRUE(r.degraded);
  EXPECT_EQ(r.status_lines, std::vector<std::string>{"robot link arm: mesh cannot be read"});
}

TEST(MonitorCycle, ArrayStampsAreCheckedAndCounted) {
  Fixture f;
  const wp::MonitorParams p = params();  // max_future 0.5 s, track_timeout 0.5 s
  const Eigen::Isometry3d here = Eigen::Isometry3d::Identity();
  // An array placement that must not be asked for a refused stamp (no tf lookup for it).
  struct Counting : wp::ArrayPlacement {
    int asked = 0;
    std::vector<wp::BoxObservation> none;
    bool place(wp::Stamp, Eigen::Isometry3d* pose,
               const std::vector<wp::BoxObservation>** boxes) override {
      ++asked;
      *pose = Eigen::Isometry3d::Identity();
      *boxes = &none;
      return true;
    }
  } placement;
  EXPECT_FALSE(f.monitor.ingest(0, kT0 + 6 * kSecond / 10, kT0, &placement));
  EXPECT_EQ(f.monitor.drops().count(wp::Drop::kFuture), 1u);
  EXPECT_FALSE(f.monitor.ingest(0, kT0 - 6 * kSecond / 10, kT0, &placement));
  EXPECT_EQ(f.monitor.drops().count(wp::Drop::kOld), 1u);
  EXPECT_EQ(placement.asked, 0);
  f.person(5.0, 0.0, kT0, kT0);  // used: the source's newest stamp is kT0
  EXPECT_FALSE(f.monitor.ingest(0, kT0 - kSecond / 10, kT0, &placement));
  EXPECT_EQ(f.monitor.drops().count(wp::Drop::kOutOfOrder), 1u);
  EXPECT_EQ(placement.asked, 0);
  EXPECT_TRUE(f.monitor.ingest(0, kT0, kT0, &placement));  // equal stamps are in order
  EXPECT_EQ(placement.asked, 1);
  EXPECT_TRUE(f.monitor.ingest(0, kT0 + 4 * kSecond / 10, kT0, here, {}));  // within max_future
  EXPECT_EQ(f.monitor.drops().total(), 3u);
  (void)p;
}

TEST(MonitorCycle, TheClockGoingBackResetsEveryStamp) {
  Fixture f;
  f.posePost();
  f.person(3.0, -1.0, kT0, kT0);
  ASSERT_EQ(f.cycle(kT0).eventCount(), 1u);
  const wp::Stamp back = kT0 - 53 * kSecond;
  ASSERT_TRUE(f.monitor.clockWentBack(back));
  f.monitor.reset();
  EXPECT_EQ(f.monitor.status().resets, 1u);
  EXPECT_EQ(f.monitor.tracks().size(), 0);
  EXPECT_FALSE(f.monitor.robot().present(0));
  EXPECT_EQ(f.monitor.sources().source(0).last_stamp, 0);
  // The old pair ends; arrays stamped in the new time are accepted again.
  const wp::CycleReport& r = f.cycle(back);
  ASSERT_EQ(r.eventCount(), 1u);
  EXPECT_EQ(r.event(0).state, wp::ContactState::kEnd);
  EXPECT_TRUE(f.monitor.ingest(0, back, back, Eigen::Isometry3d::Identity(), {}));
  EXPECT_FALSE(f.monitor.clockWentBack(back));
}

TEST(MonitorCycle, AFailedCycleReportsNothingAndSaysWhy) {
  Fixture f;
  f.posePost();
  f.person(3.0, -1.0, kT0, kT0);
  f.cycle(kT0);
  f.monitor.cycleFailed(kT0 + kSecond / 30, "boom");
  const wp::CycleReport& r = f.monitor.report();
  EXPECT_EQ(r.eventCount(), 0u);
  EXPECT_TRUE(r.degraded);
  EXPECT_EQ(r.status_lines, std::vector<std::string>{"cycle failed: boom"});
  EXPECT_EQ(f.monitor.drops().count(wp::Drop::kCycleFailure), 1u);
}

TEST(MonitorCycle, TheRobotCentreSteersTheCap) {
  wp::MonitorParams p = params();
  p.max_tracks = 1;
  wp::RobotBodySpec s = post();
  wp::Monitor monitor(p, {s}, {"/boxes"}, false, nullptr);
  wp::BodyMotion at;
  at.position = {10, 0, 0};
  ASSERT_TRUE(monitor.poseRobot(0, at));
  EXPECT_TRUE(monitor.robot().centre().isApprox(Eigen::Vector3d(10, 0, 0)));
  wp::BoxObservation near, far;
  near.id = "near";
  near.position = {9, 0, 0};
  far.id = "far";
  far.position = {0, 0, 0};
  monitor.noteReceipt(0, kT0);
  ASSERT_TRUE(monitor.ingest(0, kT0, kT0, Eigen::Isometry3d::Identity(), {far, near}));
  ASSERT_EQ(monitor.tracks().size(), 1);
  EXPECT_EQ(monitor.tracks().track(0).key, "near");
}

TEST(MonitorCycle, NewParametersTakeEffectAtTheNextCycle) {
  Fixture f;
  f.posePost();
  f.person(5.0, -2.0, kT0, kT0);  // gap 4 m at 2 m/s: contact in 2.0 s
  const wp::CycleReport& r0 = f.cycle(kT0);
  ASSERT_EQ(r0.eventCount(), 1u);
  EXPECT_NEAR(r0.event(0).time_to_contact, 2.0, 1e-6);
  EXPECT_EQ(r0.levels[0], wp::Level::kWarning);  // person warning_time 2.5 s
  // Tighter person thresholds, a 0.5 m person margin and a 1.5 s horizon.
  wp::MonitorParams p = params();
  p.labels["person"].warning_time = 1.0;
  p.labels["person"].critical_time = 0.5;
  p.labels["person"].margin = 0.5;
  p.horizon = 1.5;
  ASSERT_TRUE(wp::validate(p).empty());
  f.monitor.setParams(p);
  const wp::BodyHandle person = f.monitor.tracks().track(0).handle;
  EXPECT_EQ(f.monitor.world().desc(person).margin, 0.5);
  // The margin closes the gap by 0.5 m: contact at 1.75 s, beyond the 1.5 s horizon -> END.
  const wp::CycleReport& r1 = f.cycle(kT0);
  ASSERT_EQ(r1.eventCount(), 1u);
  EXPECT_EQ(r1.event(0).state, wp::ContactState::kEnd);
  // Back to a 5 s horizon: BEGIN again, 1.75 s, NOTICE under the new thresholds.
  p.horizon = 5.0;
  f.monitor.setParams(p);
  const wp::CycleReport& r2 = f.cycle(kT0);
  ASSERT_EQ(r2.eventCount(), 1u);
  EXPECT_NEAR(r2.event(0).time_to_contact, 1.75, 1e-6);
  EXPECT_EQ(r2.levels[0], wp::Level::kNotice);
  // The robot margin applies to robot bodies at once.
  p.robot_margin = 0.25;
  f.monitor.setParams(p);
  EXPECT_EQ(f.monitor.world().desc(f.monitor.robot().handle(0)).margin, 0.25);
  EXPECT_NEAR(f.cycle(kT0).event(0).time_to_contact, 1.625, 1e-6);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
