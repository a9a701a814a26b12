// The track table's rules, ROS-free: boxes become tracks, duplicates, the cap (nearest to the
// robot win, farther tracks evicted), relabelling, size hysteresis, stale stamps, expiry and
// latency compensation. Expected values are worked out by hand from the inputs; the random
// test compares the table with a plain std::map model of which keys must be tracked.

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <list>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "workspace_proximity/rules/track_table.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr wp::Stamp kSecond = 1000000000;

struct Recorder : wp::RejectionSink {
  std::vector<wp::Drop> reasons;
  std::vector<std::string> ids;
  void onRejection(const wp::Rejection& r) override {
    reasons.push_back(r.reason);
    ids.emplace_back(r.id);
  }
};

struct Fixture {
  explicit Fixture(int max_tracks = 100) : labels(params()), table(&world, &labels, max_tracks, wp::BoxLimits(), &drops, &sink) {}
  static wp::MonitorParams params() {
    wp::MonitorParams p;
    p.labels["default"].margin = 0.1;
    p.labels["person"].margin = 0.2;
    p.labels["forklift"].margin = 0.3;
    return p;
  }
  // Ids and labels must outlive the observations: they live in `names`.
  wp::BoxObservation box(const std::string& id, double x, double y = 0.0,
                         const std::string& label = "person") {
    names.push_back(id);
    names.push_back(label);
    wp::BoxObservation b;
    b.id = *std::next(names.rbegin());
    b.label = names.back();
    b.position = {x, y, 0.9};
    b.dimensions = {0.5, 0.5, 1.8};
    return b;
  }
  void ingest(const std::vector<wp::BoxObservation>& boxes, wp::Stamp stamp,
              std::string_view qualifier = "", const Eigen::Vector3d& centre = Eigen::Vector3d::Zero(),
              const Eigen::Isometry3d& frame = Eigen::Isometry3d::Identity()) {
    wp::ArrayContext a;
    a.source = "/boxes";
    a.qualifier = qualifier;
    a.stamp = stamp;
    a.fixed_from_frame = frame;
    a.robot_centre = centre;
    table.ingest(a, boxes);
  }
  // Every track's body is in the world under the track's key, and the slot maps back to it.
  void expectConsistent() {
    EXPECT_EQ(world.bodyCount(), table.size());
    for (int i = 0; i < table.size(); ++i) {
      const wp::Track& t = table.track(i);
      ASSERT_TRUE(world.contains(t.handle));
      EXPECT_EQ(world.desc(t.handle).id, t.key);
      EXPECT_EQ(table.trackOfSlot(t.handle.index), i);
      EXPECT_EQ(table.find(t.key), i);
    }
  }

  std::list<std::string> names;
  wp::ProximityWorld world;
  wp::LabelTable labels;
  wp::DropCounters drops;
  Recorder sink;
  wp::TrackTable table;
};

}  // namespace

TEST(TrackTable, BoxesBecomeTracksInTheFixedFrame) {
  Fixture f;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  frame.translation() = Eigen::Vector3d(10, 0, 0);
  wp::BoxObservation b = f.box("7", 1.0, 2.0);
  b.linear_velocity = {1, 0, 0};
  f.ingest({b, f.box("8", 3.0, 0.0, "forklift")}, 5 * kSecond, "", Eigen::Vector3d::Zero(), frame);
  ASSERT_EQ(f.table.size(), 2);
  f.expectConsistent();
  const wp::Track& t = f.table.track(f.table.find("7"));
  EXPECT_EQ(t.label, "person");
  EXPECT_EQ(t.stamp, 5 * kSecond);
  EXPECT_TRUE(t.motion.position.isApprox(Eigen::Vector3d(11, 2, 0.9)));
  EXPECT_EQ(f.world.desc(t.handle).margin, 0.2);  // the person label's margin
  EXPECT_EQ(f.world.desc(f.table.track(f.table.find("8")).handle).margin, 0.3);
  EXPECT_EQ(f.drops.total(), 0u);
}

TEST(TrackTable, QualifiedIdsKeepTwoSourcesApart) {
  Fixture f;
  f.ingest({f.box("7", 1.0)}, kSecond, "/left");
  f.ingest({f.box("7", 2.0)}, kSecond, "/right");
  ASSERT_EQ(f.table.size(), 2);
  EXPECT_GE(f.table.find("/left/7"), 0);
  EXPECT_GE(f.table.find("/right/7"), 0);
  EXPECT_EQ(f.table.find("7"), -1);
  f.expectConsistent();
}

TEST(TrackTable, ADuplicateIdInOneArrayIsDroppedAndTheFirstUsed) {
  Fixture f;
  f.ingest({f.box("7", 1.0), f.box("7", 5.0)}, kSecond);
  ASSERT_EQ(f.table.size(), 1);
  EXPECT_DOUBLE_EQ(f.table.track(0).motion.position.x(), 1.0);
  EXPECT_EQ(f.drops.count(wp::Drop::kDuplicateId), 1u);
  ASSERT_EQ(f.sink.reasons.size(), 1u);
  EXPECT_EQ(f.sink.ids[0], "7");
  // The same id in the next array is an update, not a duplicate.
  f.ingest({f.box("7", 2.0)}, 2 * kSecond);
  EXPECT_DOUBLE_EQ(f.table.track(0).motion.position.x(), 2.0);
  EXPECT_EQ(f.drops.count(wp::Drop::kDuplicateId), 1u);
}

TEST(TrackTable, BadBoxesAreDroppedAndTheRestUsed) {
  Fixture f;
  wp::BoxObservation bad = f.box("bad", 1.0);
  bad.dimensions.x() = std::numeric_limits<double>::quiet_NaN();
  wp::BoxObservation far = f.box("far", 1.0);
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  f.ingest({bad, f.box("good", 2.0)}, kSecond);
  // A frame that carries an accepted box past the core's limits: dropped as core limits.
  frame.translation() = Eigen::Vector3d(2e7, 0, 0);
  f.ingest({far}, kSecond, "", Eigen::Vector3d::Zero(), frame);
  EXPECT_EQ(f.table.size(), 1);
  EXPECT_GE(f.table.find("good"), 0);
  EXPECT_EQ(f.drops.count(wp::Drop::kNonFinite), 1u);
  EXPECT_EQ(f.drops.count(wp::Drop::kCoreLimits), 1u);
  f.expectConsistent();
}

TEST(TrackTable, TheCapKeepsTheBoxesNearestTheRobot) {
  Fixture f(2);
  // Robot centre at x = 0: boxes at 4, 1, 3, 2 m. The two nearest (1 and 2) are kept.
  f.ingest({f.box("d4", 4.0), f.box("d1", 1.0), f.box("d3", 3.0), f.box("d2", 2.0)}, kSecond);
  ASSERT_EQ(f.table.size(), 2);
  EXPECT_GE(f.table.find("d1"), 0);
  EXPECT_GE(f.table.find("d2"), 0);
  EXPECT_EQ(f.drops.count(wp::Drop::kCap), 2u);
  // A nearer newcomer evicts the farthest track (d2); a farther one is refused.
  f.ingest({f.box("d05", 0.5)}, 2 * kSecond);
  EXPECT_GE(f.table.find("d05"), 0);
  EXPECT_EQ(f.table.find("d2"), -1);
  EXPECT_GE(f.table.find("d1"), 0);
  EXPECT_EQ(f.drops.count(wp::Drop::kCap), 3u);
  f.ingest({f.box("d9", 9.0)}, 3 * kSecond);
  EXPECT_EQ(f.table.find("d9"), -1);
  EXPECT_EQ(f.drops.count(wp::Drop::kCap), 4u);
  EXPECT_EQ(f.table.size(), 2);
  f.expectConsistent();
  // The cap measures from the robot's centre, wherever it is.
  f.ingest({f.box("d9", 9.0)}, 4 * kSecond, "", Eigen::Vector3d(9, 0, 0));
  EXPECT_GE(f.table.find("d9"), 0);
  EXPECT_EQ(f.table.find("d05"), -1);
}

TEST(TrackTable, ANewLabelRestartsTheTrack) {
  Fixture f;
  f.ingest({f.box("7", 1.0, 0.0, "person")}, kSecond);
  const wp::BodyHandle before = f.table.track(0).handle;
  f.ingest({f.box("7", 1.0, 0.0, "forklift")}, 2 * kSecond);
  ASSERT_EQ(f.table.size(), 1);
  const wp::Track& t = f.table.track(0);
  EXPECT_NE(t.handle, before);
  EXPECT_EQ(t.label, "forklift");
  EXPECT_EQ(f.world.desc(t.handle).margin, 0.3);
  EXPECT_EQ(f.drops.count(wp::Drop::kRelabelled), 1u);
  f.expectConsistent();
  // Its old pairs END at the next predict: the old body is removed from the world.
  EXPECT_EQ(f.world.bodyCount(), 1);
}

TEST(TrackTable, SizesGrowAtOnceAndShrinkOnlyWhenClearlySmaller) {
  Fixture f;
  f.ingest({f.box("7", 1.0)}, kSecond);
  const wp::BodyHandle h = f.table.track(0).handle;
  auto half = [&] { return f.world.desc(h).shape.half_extents.x(); };
  wp::BoxObservation b = f.box("7", 1.0);
  b.dimensions.x() = 0.502;  // 1 mm more per side: grows
  f.ingest({b}, 2 * kSecond);
  EXPECT_DOUBLE_EQ(half(), 0.251);
  b.dimensions.x() = 0.44;  // 3 cm smaller per side: kept
  f.ingest({b}, 3 * kSecond);
  EXPECT_DOUBLE_EQ(half(), 0.251);
  b.dimensions.x() = 0.38;  // 6 cm smaller per side: shrinks
  f.ingest({b}, 4 * kSecond);
  EXPECT_DOUBLE_EQ(half(), 0.19);
  EXPECT_EQ(f.table.track(0).handle, h);  // same body: its pairs continue
}

TEST(TrackTable, AnOlderObservationNeverReplacesANewerOne) {
  Fixture f;
  f.ingest({f.box("7", 1.0)}, 2 * kSecond);
  f.ingest({f.box("7", 5.0)}, 1 * kSecond);
  EXPECT_DOUBLE_EQ(f.table.track(0).motion.position.x(), 1.0);
  EXPECT_EQ(f.table.track(0).stamp, 2 * kSecond);
}

TEST(TrackTable, ExpiryDropsOldTracksAndKeepsTheIndexDense) {
  Fixture f;
  f.ingest({f.box("a", 1.0), f.box("b", 2.0)}, 1 * kSecond);
  f.ingest({f.box("c", 3.0), f.box("d", 4.0)}, 2 * kSecond);
  f.ingest({f.box("a", 1.5)}, 3 * kSecond);
  // At t = 3.4 s with a 0.5 s timeout: b (t = 1) goes; c, d (t = 2) go; a (t = 3) stays.
  const int slot_b = f.table.track(f.table.find("b")).handle.index;
  f.table.expire(3 * kSecond + 400000000, 0.5);
  ASSERT_EQ(f.table.size(), 1);
  EXPECT_GE(f.table.find("a"), 0);
  EXPECT_EQ(f.table.trackOfSlot(slot_b), -1);
  f.expectConsistent();
  // Exactly at the timeout a track is kept (older than, not as old as).
  f.table.expire(3 * kSecond + 500000000, 0.5);
  EXPECT_EQ(f.table.size(), 1);
}

TEST(TrackTable, AdvanceMovesEveryTrackFromItsStampToNow) {
  Fixture f;
  wp::BoxObservation b = f.box("7", 1.0);
  b.linear_velocity = {2.0, -1.0, 0.0};
  f.ingest({b}, 1 * kSecond);
  f.table.advance(1 * kSecond + 250000000);  // 0.25 s later
  const wp::BodyMotion& m = f.world.motion(f.table.track(0).handle);
  EXPECT_NEAR(m.position.x(), 1.5, 1e-12);
  EXPECT_NEAR(m.position.y(), -0.25, 1e-12);
  // The track keeps its observation; only the world's body moves.
  EXPECT_DOUBLE_EQ(f.table.track(0).motion.position.x(), 1.0);
}

TEST(TrackTable, ClearRemovesEveryBody) {
  Fixture f;
  f.ingest({f.box("a", 1.0), f.box("b", 2.0)}, kSecond);
  const int slot = f.table.track(0).handle.index;
  f.table.clear();
  EXPECT_EQ(f.table.size(), 0);
  EXPECT_EQ(f.world.bodyCount(), 0);
  EXPECT_EQ(f.table.trackOfSlot(slot), -1);
}

TEST(TrackTable, RandomArraysMatchAPlainModel) {
  // Model: which keys must be tracked (the newest stamp of each), given arrays of random
  // subsets of 30 ids, in id order or shuffled (the table tries the track a position had
  // last time first: any order must find the right track), and expiry with a 0.3 s timeout.
  // No cap, valid boxes only. Each box's x says its id: every track holds its own box.
  Fixture f;
  std::mt19937 rng(11);
  std::map<std::string, wp::Stamp> model;
  for (int step = 0; step < 400; ++step) {
    const wp::Stamp now = (step + 1) * kSecond / 10;
    std::vector<wp::BoxObservation> boxes;
    for (int id = 0; id < 30; ++id) {
      if (rng() % 3 != 0) continue;
      boxes.push_back(f.box("id" + std::to_string(id), 0.1 * id, static_cast<double>(rng() % 7)));
      model["id" + std::to_string(id)] = now;
    }
    if (step % 4 >= 2) std::shuffle(boxes.begin(), boxes.end(), rng);
    f.ingest(boxes, now);
    for (const wp::BoxObservation& b : boxes) {
      const int i = f.table.find(std::string(b.id));
      ASSERT_GE(i, 0) << b.id;
      EXPECT_EQ(f.table.track(i).motion.position.x(), b.position.x()) << b.id;
      EXPECT_EQ(f.table.track(i).stamp, now) << b.id;
    }
    f.table.expire(now + kSecond / 20, 0.3);
    for (auto it = model.begin(); it != model.end();) {
      it = wp::secondsBetween(it->second, now + kSecond / 20) > 0.3 ? model.erase(it) : std::next(it);
    }
    ASSERT_EQ(f.table.size(), static_cast<int>(model.size())) << "step " << step;
    for (const auto& kv : model) {
      const int i = f.table.find(kv.first);
      ASSERT_GE(i, 0) << kv.first;
      EXPECT_EQ(f.table.track(i).stamp, kv.second);
    }
    f.expectConsistent();
    if (step % 50 == 49) f.world.predict(1.0);  // frees removed slots, so slots get reused
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
