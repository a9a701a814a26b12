// The one cycle runner (CycleRunner) with a recording feed and output: the order of a cycle's
// parts, the reset when the clock went back, a failure anywhere still reporting (and saying
// why), and which stages are timed. No wall-clock value is asserted: only which laps exist and
// that they fit in the cycle's time.

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "monitor_scenes.hpp"  // test/shared
#include "workspace_proximity/rules/cycle_runner.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;
constexpr wp::Stamp kT0 = 1000 * kSecond;

// Records the calls; poses the robot's post every update, and throws when told to.
class Feed : public wp::CycleFeed {
 public:
  explicit Feed(wp::Monitor* monitor) : monitor_(monitor) {}
  void reset(wp::Stamp now) override { log.push_back("reset " + std::to_string(now)); }
  void update(wp::Stamp) override {
    log.push_back("update");
    if (!throw_in_update.empty()) throw std::runtime_error(throw_in_update);
    monitor_->poseRobot(0, wp::BodyMotion());
  }
  void failed(const std::string& what) override { log.push_back("failed " + what); }
  std::vector<std::string> log;
  std::string throw_in_update;

 private:
  wp::Monitor* monitor_;
};

class Output : public wp::CycleOutput {
 public:
  explicit Output(std::vector<std::string>* log) : log_(log) {}
  void safety(const wp::CycleReport& report, const wp::ProximityWorld&,
              const wp::CycleRun& run) override {
    // The verdict is complete when it goes out: the scale, and DEGRADED with its reason.
    log_->push_back(std::string("safety") + (report.degraded ? " degraded" : "") +
                    (run.failed ? " failed" : ""));
    scales.push_back(report.ssm.speed_scale);
  }
  void handOff() override { log_->push_back("hand-off"); }
  void contacts(const wp::CycleReport& report, const wp::ProximityWorld&) override {
    log_->push_back(std::string("contacts") + (report.degraded ? " degraded" : ""));
    if (throw_in_contacts) {
      throw_in_contacts = false;
      throw std::runtime_error("publisher gone");
    }
  }
  void rest(const wp::CycleReport& report, const wp::ProximityWorld&,
            const wp::CycleRun& run) override {
    log_->push_back(std::string("rest") + (run.failed ? " failed" : "") +
                    (run.reset ? " reset" : ""));
    stamps.push_back(report.stamp);
  }
  bool throw_in_contacts = false;
  std::vector<wp::Stamp> stamps;
  std::vector<double> scales;  // the speed scale each safety() saw

 private:
  std::vector<std::string>* log_;
};

struct Fixture {
  Fixture()
      : monitor(wp_test::marginFreeParams(2.0), {wp_test::robotBox("post", {0.5, 0.5, 0.5})},
                {"/boxes"}, false, nullptr),
        runner(&monitor), feed(&monitor), out(&feed.log) {}
  // An empty scene from /boxes at `now`: nothing there (OK once the post is posed).
  void emptyScene(wp::Stamp now) {
    monitor.noteReceipt(0, now);
    ASSERT_TRUE(monitor.ingest(0, now, now, Eigen::Isometry3d::Identity(), {}));
  }
  wp::Monitor monitor;
  wp::CycleRunner runner;
  Feed feed;
  Output out;
};

}  // namespace

TEST(CycleRunner, ACycleIsTheFeedThenTheMonitorThenTheSafetyOutputThenTheContactsThenTheRest) {
  Fixture f;
  f.emptyScene(kT0);
  const wp::CycleRun run = f.runner.run(kT0, &f.feed, &f.out);
  EXPECT_FALSE(run.reset);
  EXPECT_FALSE(run.failed);
  EXPECT_EQ(f.feed.log,
            (std::vector<std::string>{"update", "safety", "hand-off", "contacts", "rest"}));
  EXPECT_EQ(f.out.stamps, std::vector<wp::Stamp>{kT0});
  // The safety output saw the cycle's finished verdict, not an earlier one.
  EXPECT_EQ(f.out.scales, std::vector<double>{f.monitor.report().ssm.speed_scale});
  EXPECT_EQ(f.monitor.status().cycles, 1u);
  EXPECT_FALSE(f.monitor.report().degraded);
}

TEST(CycleRunner, TheClockGoingBackResetsTheFeedAndTheMonitorFirst) {
  Fixture f;
  f.emptyScene(kT0);
  f.runner.run(kT0, &f.feed, &f.out);
  f.feed.log.clear();
  const wp::Stamp back = kT0 - 53 * kSecond;
  const wp::CycleRun run = f.runner.run(back, &f.feed, &f.out);
  EXPECT_TRUE(run.reset);
  EXPECT_FALSE(run.failed);
  EXPECT_EQ(f.feed.log, (std::vector<std::string>{"reset " + std::to_string(back), "update",
                                                  "safety degraded", "hand-off",
                                                  "contacts degraded", "rest reset"}));
  EXPECT_EQ(f.monitor.status().resets, 1u);
  EXPECT_EQ(f.monitor.sources().source(0).last_receipt, 0);  // forgotten: no data yet
  EXPECT_EQ(f.monitor.status().last_cycle, back);
  // Once: the next cycle, later, is no reset.
  f.feed.log.clear();
  EXPECT_FALSE(f.runner.run(back + kSecond / 10, &f.feed, &f.out).reset);
}

TEST(CycleRunner, AFailureStillReportsAndSaysWhy) {
  Fixture f;
  f.emptyScene(kT0);
  f.runner.run(kT0, &f.feed, &f.out);
  const double last_ms = f.runner.lastCycleMs();
  f.feed.log.clear();
  f.feed.throw_in_update = "tf exploded";
  const wp::CycleRun run = f.runner.run(kT0 + kSecond / 10, &f.feed, &f.out);
  EXPECT_TRUE(run.failed);
  EXPECT_EQ(f.feed.log, (std::vector<std::string>{"update", "failed tf exploded",
                                                  "safety degraded failed", "hand-off",
                                                  "contacts degraded", "rest failed"}));
  const wp::CycleReport& r = f.monitor.report();
  EXPECT_EQ(r.stamp, kT0 + kSecond / 10);
  EXPECT_EQ(r.eventCount(), 0u);
  EXPECT_EQ(r.status_lines, std::vector<std::string>{"cycle failed: tf exploded"});
  // The failed cycle's safety output is the failure's verdict: at most ~ssm/degraded_scale.
  EXPECT_LE(f.out.scales.back(), f.monitor.params().ssm.degraded_scale);
  EXPECT_EQ(f.out.scales.back(), r.ssm.speed_scale);
  EXPECT_EQ(f.monitor.drops().count(wp::Drop::kCycleFailure), 1u);
  EXPECT_EQ(f.monitor.status().cycles, 1u);  // the failed one is not counted
  EXPECT_EQ(f.runner.lastCycleMs(), last_ms);  // nor timed
}

TEST(CycleRunner, AnOutputThatThrowsFailsTheCycleWhichReportsAgain) {
  Fixture f;
  f.emptyScene(kT0);
  f.out.throw_in_contacts = true;
  const wp::CycleRun run = f.runner.run(kT0, &f.feed, &f.out);
  EXPECT_TRUE(run.failed);
  EXPECT_EQ(f.feed.log, (std::vector<std::string>{"update", "safety", "hand-off", "contacts",
                                                  "failed publisher gone",
                                                  "safety degraded failed", "hand-off",
                                                  "contacts degraded", "rest failed"}));
}

TEST(CycleRunner, TheStagesAreLappedWithinTheCycleAndOffCycleStagesNoted) {
  Fixture f;
  f.emptyScene(kT0);
  f.runner.run(kT0, &f.feed, &f.out);
  const wp::CycleTiming& t = f.runner.timing();
  // Input, near, ssm, safety, predict, report and contacts are consecutive laps from the
  // cycle's start: together no longer than the whole cycle, which ends after the rest.
  double laps = 0.0, to_safety = 0.0;
  for (wp::CycleStage s : {wp::CycleStage::kInput, wp::CycleStage::kNear, wp::CycleStage::kSsm,
                           wp::CycleStage::kSafety, wp::CycleStage::kPredict,
                           wp::CycleStage::kReport, wp::CycleStage::kContacts}) {
    EXPECT_GE(t.last(s), 0.0) << wp::CycleTiming::name(s);
    laps += t.last(s);
    if (s == wp::CycleStage::kSafety) to_safety = laps;
  }
  EXPECT_LE(laps, f.runner.lastCycleMs());
  // The start to the safety output: read after the first three laps and within the fourth
  // (which also holds the hand-off).
  EXPECT_GE(t.last(wp::CycleStage::kToSafety),
            (to_safety - t.last(wp::CycleStage::kSafety)) * (1.0 - 1e-12));
  EXPECT_LE(t.last(wp::CycleStage::kToSafety), to_safety * (1.0 + 1e-12));
  // The start to the contacts published: after every lap, within the whole cycle.
  EXPECT_GE(t.last(wp::CycleStage::kToContacts), laps * (1.0 - 1e-12));
  EXPECT_LE(t.last(wp::CycleStage::kToContacts), f.runner.lastCycleMs() * (1.0 + 1e-12));
  // The broad phase is part of the predict lap (the world's own stage times).
  EXPECT_LE(t.last(wp::CycleStage::kBroad), t.last(wp::CycleStage::kPredict));
  // Every stage has its own name in the summary.
  for (int i = 0; i < wp::CycleTiming::kStages; ++i) {
    EXPECT_NE(std::string(wp::CycleTiming::name(static_cast<wp::CycleStage>(i))), "?");
  }
  EXPECT_GE(f.runner.maxCycleMs(), f.runner.lastCycleMs());
  f.runner.noteTime(wp::CycleStage::kMarkers, 2.5);
  EXPECT_EQ(t.last(wp::CycleStage::kMarkers), 2.5);
  // Without a feed or outputs (the benchmarks): the monitor's cycle alone.
  wp::CycleRunner bare(&f.monitor);
  EXPECT_FALSE(bare.run(kT0 + kSecond / 10, nullptr, nullptr).failed);
  EXPECT_EQ(f.monitor.status().cycles, 2u);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
