// The perception front ends' health in the monitor (perception_health.hpp), ROS-free: the
// DEGRADED lines and the unseen share worked out by hand for never heard, fresh, degraded and
// silent status topics; and through the monitor's cycle: a degraded front end makes the
// cycle DEGRADED naming the sensor, and the speed scale goes to degraded_scale (0).

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "workspace_proximity/rules/monitor.hpp"
#include "workspace_proximity/rules/perception_health.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kT0 = 1000 * kSecond;

std::vector<std::string> lines(const wp::PerceptionHealth& h, wp::Stamp now, double timeout = 1.0) {
  std::vector<std::string> out;
  h.statusLines(now, timeout, &out);
  return out;
}

}  // namespace

TEST(PerceptionHealth, NoTopicsNoLinesAndNoShare) {
  const wp::PerceptionHealth h;
  EXPECT_TRUE(lines(h, kT0).empty());
  EXPECT_TRUE(std::isnan(h.unseenShare(kT0, 1.0)));
}

TEST(PerceptionHealth, NeverHeardIsDegraded) {
  const wp::PerceptionHealth h({"/a/perception_status"});
  EXPECT_EQ(lines(h, kT0), std::vector<std::string>{"perception /a/perception_status: no status yet"});
  EXPECT_TRUE(std::isnan(h.unseenShare(kT0, 1.0)));
}

TEST(PerceptionHealth, FreshDegradedAndSilentStatuses) {
  wp::PerceptionHealth h({"/a", "/b"});
  h.onStatus(0, kT0, false, {}, 0.25);
  h.onStatus(1, kT0, true, {"/cam/points: no usable frame for 1.20 s", "unseen share 0.700 above 0.300"}, 0.7);
  EXPECT_EQ(lines(h, kT0 + kSecond / 2),
            (std::vector<std::string>{"perception /b: /cam/points: no usable frame for 1.20 s",
                                      "perception /b: unseen share 0.700 above 0.300"}));
  EXPECT_DOUBLE_EQ(h.unseenShare(kT0 + kSecond / 2, 1.0), 0.7);  // the larger
  // /b recovers; /a goes silent: 1.5 s after its last status, with a 1 s timeout.
  h.onStatus(1, kT0 + kSecond, false, {}, 0.1);
  EXPECT_EQ(lines(h, kT0 + 3 * kSecond / 2),
            std::vector<std::string>{"perception /a: no status for 1.50 s"});
  EXPECT_TRUE(std::isnan(h.unseenShare(kT0 + 3 * kSecond / 2, 1.0)));  // /a's is unknown now
  h.onStatus(0, kT0 + 3 * kSecond / 2, false, {}, 0.05);
  EXPECT_TRUE(lines(h, kT0 + 3 * kSecond / 2).empty());
  EXPECT_DOUBLE_EQ(h.unseenShare(kT0 + 3 * kSecond / 2, 1.0), 0.1);
  // Degraded without a reason is still degraded; an unknown share is unknown.
  h.onStatus(0, kT0 + 2 * kSecond, true, {}, std::nan(""));
  EXPECT_EQ(lines(h, kT0 + 2 * kSecond),
            std::vector<std::string>{"perception /a: degraded (no reason given)"});
  EXPECT_TRUE(std::isnan(h.unseenShare(kT0 + 2 * kSecond, 1.0)));
  h.reset();
  EXPECT_EQ(lines(h, kT0 + 2 * kSecond).size(), 2u);  // never heard again
}

TEST(PerceptionHealth, ADegradedFrontEndStopsTheMonitorsScale) {
  wp::MonitorParams p = wp_test::marginFreeParams(5.0, wp::LabelSettings{0.0, 2.5, 0.5, 0.1, 0.05});
  p.ssm.enabled = true;
  p.ssm.degraded_scale = 0.0;
  p.source_timeout = 1.0;
  p.perception_status_topics = {"/perception_status"};
  wp::Monitor monitor(p, {wp_test::robotBox("post", {0.5, 0.5, 0.5})}, {"/perceived_objects"}, false,
                      nullptr);
  wp::CycleTiming timing;
  wp::StageClock clock(&timing);
  auto cycle = [&](wp::Stamp now) -> const wp::CycleReport& {
    monitor.noteReceipt(0, now);
    EXPECT_TRUE(monitor.ingest(0, now, now, Eigen::Isometry3d::Identity(), {}));
    EXPECT_TRUE(monitor.poseRobot(0, wp::BodyMotion()));
    return monitor.cycle(now, &clock);
  };
  // Every other input fine; the front end degraded, naming its camera.
  monitor.perception().onStatus(0, kT0, true, {"/cam/points: frame 'cam' not placed by tf"}, 0.2);
  const wp::CycleReport& r = cycle(kT0 + kSecond / 10);
  EXPECT_TRUE(r.degraded);
  ASSERT_EQ(r.status_lines.size(), 1u);
  EXPECT_EQ(r.status_lines[0], "perception /perception_status: /cam/points: frame 'cam' not placed by tf");
  EXPECT_EQ(r.ssm.speed_scale, 0.0);
  EXPECT_DOUBLE_EQ(r.unseen_share, 0.2);
  // Healthy again: OK, scale 1 (nothing within reach), the share as reported.
  monitor.perception().onStatus(0, kT0 + kSecond / 5, false, {}, 0.1);
  const wp::CycleReport& ok = cycle(kT0 + kSecond / 4);
  EXPECT_FALSE(ok.degraded) << (ok.status_lines.empty() ? "" : ok.status_lines[0]);
  EXPECT_DOUBLE_EQ(ok.unseen_share, 0.1);
  // Its status topic silent for longer than source_timeout: DEGRADED again, scale 0.
  const wp::Stamp later = kT0 + kSecond / 5 + 3 * kSecond / 2;
  const wp::CycleReport& silent = cycle(later);
  EXPECT_TRUE(silent.degraded);
  ASSERT_EQ(silent.status_lines.size(), 1u);
  EXPECT_EQ(silent.status_lines[0], "perception /perception_status: no status for 1.50 s");
  EXPECT_EQ(silent.ssm.speed_scale, 0.0);
  EXPECT_TRUE(std::isnan(silent.unseen_share));
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
