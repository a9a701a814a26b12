// Foreign tracker messages through the input bridge (MonitorBridges: no master, a tf2
// BufferCore): the messages Debian's genpy serialized from the upstream definitions
// (test/foreign/fixtures/, their values in the .txt beside each) become tracks with their
// ids, sizes and positions; an unknown md5 or type name and malformed bytes are refused by
// name, the first two DEGRADED for as long as they last; id-less types go through the tracker.

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <tf2/buffer_core.h>

#include "workspace_proximity/ros/monitor_bridges.hpp"

namespace wp = workspace_proximity;

namespace {

struct Fixture {
  std::string type, md5;
  std::vector<std::uint8_t> bytes;
  std::vector<Eigen::Vector3d> positions;  // as the generator put them in
};

Fixture load(const std::string& name) {
  Fixture f;
  const std::string base = std::string(WP_SOURCE_DIR) + "/test/foreign/fixtures/" + name;
  std::ifstream bin(base + ".bin", std::ios::binary);
  f.bytes.assign(std::istreambuf_iterator<char>(bin), std::istreambuf_iterator<char>());
  std::ifstream txt(base + ".txt");
  std::string word;
  txt >> word >> f.type >> f.md5;
  while (txt >> word) {
    Eigen::Vector3d p;
    double rest;
    txt >> p.x() >> p.y() >> p.z();
    for (int i = 0; i < 4; ++i) txt >> rest;
    f.positions.push_back(p);
  }
  return f;
}

class ForeignInput : public ::testing::Test {
 protected:
  ForeignInput() : tf_(ros::Duration(100.0)) {
    // The fixtures' frames, all at the fixed frame's origin but "odom", one metre along x.
    for (const char* frame : {"map", "odom", "base", "laser", "camera"}) {
      geometry_msgs::TransformStamped t;
      t.header.frame_id = "world";
      t.child_frame_id = frame;
      t.transform.translation.x = std::strcmp(frame, "odom") == 0 ? 1.0 : 0.0;
      t.transform.rotation.w = 1.0;
      tf_.setTransform(t, "test", true);
    }
    params_.fixed_frame = "world";
    params_.track_timeout = 5.0;
    bridges_ = std::make_unique<wp::MonitorBridges>(params_, std::vector<wp::RobotBodySpec>{},
                                                    std::vector<std::string>{"/people"}, false,
                                                    &tf_, nullptr);
  }

  // One message of `f` (with `md5` instead of its own when given) at `now`, then a cycle.
  void feed(const Fixture& f, wp::Stamp now, std::size_t size, const std::string& type,
            const std::string& md5, const std::string& definition = "") {
    std::uint8_t* bytes = bridges_->foreignBytes(0, size);
    std::memcpy(bytes, f.bytes.data(), size);
    bridges_->onForeign(0, type, md5, definition, now);
    bridges_->run(now, nullptr);
  }
  void feed(const Fixture& f, wp::Stamp now) { feed(f, now, f.bytes.size(), f.type, f.md5); }

  const wp::CycleReport& report() const { return bridges_->monitor().report(); }
  bool statusNames(const std::string& words) const {
    for (const std::string& line : report().status_lines) {
      if (line.find(words) != std::string::npos) return true;
    }
    return false;
  }
  std::uint64_t drops(wp::Drop reason) const { return bridges_->monitor().drops().count(reason); }

  wp::MonitorParams params_;
  tf2::BufferCore tf_;
  std::unique_ptr<wp::MonitorBridges> bridges_;
};

constexpr wp::Stamp kSecond = 1000000000;

}  // namespace

TEST_F(ForeignInput, SpencerTracksBecomeTracksWithTheirIdsAndThePersonSize) {
  const Fixture f = load("spencer_v2");  // stamped 10 s + 500 ns, frame map
  feed(f, 10 * kSecond + kSecond / 10);
  const wp::TrackTable& tracks = bridges_->monitor().tracks();
  ASSERT_EQ(tracks.size(), 2);
  for (int i = 0; i < 2; ++i) {
    const int t = tracks.find(std::to_string(100 + i));
    ASSERT_GE(t, 0) << "track " << 100 + i;
    EXPECT_EQ(tracks.track(t).label, "person");
    EXPECT_EQ(tracks.track(t).stamp, 10 * kSecond + 500);
    EXPECT_LT((tracks.track(t).motion.position - f.positions[i]).norm(), 1e-12);
    // The person's size for a point: 0.6 x 0.6 x 1.8 m (the bare shape; margins apart).
    EXPECT_LT((tracks.track(t).half - Eigen::Vector3d(0.3, 0.3, 0.9)).norm(), 1e-12);
  }
  EXPECT_FALSE(report().degraded) << report().status_lines.front();
}

TEST_F(ForeignInput, PositionsAreMovedIntoTheFixedFrame) {
  const Fixture f = load("leg_tracker");  // frame odom: 1 m along x in world
  feed(f, 14 * kSecond + kSecond / 10);
  const wp::TrackTable& tracks = bridges_->monitor().tracks();
  ASSERT_EQ(tracks.size(), 2);
  const int t = tracks.find("40");
  ASSERT_GE(t, 0);
  EXPECT_LT((tracks.track(t).motion.position - (f.positions[0] + Eigen::Vector3d(1, 0, 0))).norm(),
            1e-12);
}

TEST_F(ForeignInput, AnUnknownMd5IsRefusedByNameForAsLongAsItLasts) {
  const Fixture f = load("people");  // stamped 11 s, frame odom
  const std::string definition = "float64 extra_field\nHeader header\nPerson[] people\n";
  for (int k = 0; k < 3; ++k) {
    feed(f, 11 * kSecond + k * kSecond / 10, f.bytes.size(), f.type,
         "0123456789abcdef0123456789abcdef", definition);
    EXPECT_TRUE(report().degraded);
    EXPECT_TRUE(statusNames("people_msgs/People md5 0123456789abcdef0123456789abcdef"));
    EXPECT_EQ(bridges_->monitor().tracks().size(), 0);
  }
  EXPECT_EQ(drops(wp::Drop::kMessageType), 3u);
  // The known version again: read, and the refusal's line is gone.
  feed(f, 11 * kSecond + 4 * kSecond / 10);
  EXPECT_EQ(bridges_->monitor().tracks().size(), 2);
  EXPECT_FALSE(statusNames("md5"));
  EXPECT_FALSE(report().degraded);
}

TEST_F(ForeignInput, UnknownTypesAreRefusedByName) {
  const Fixture f = load("people");
  feed(f, 11 * kSecond, f.bytes.size(), "my_tracker/People", f.md5);
  EXPECT_TRUE(statusNames("my_tracker/People"));
  EXPECT_EQ(bridges_->monitor().tracks().size(), 0);
  EXPECT_EQ(drops(wp::Drop::kMessageType), 1u);
}

TEST_F(ForeignInput, ObstacleSegmentsAndCirclesGoThroughTheTracker) {
  // obstacle_detector's segments and circles have no ids: read (no refusal), tentative tracks
  // of the multi-object tracker (confirmed at the second hit), so no track yet.
  const Fixture o = load("obstacles");  // stamped 16 s, frame map
  feed(o, 16 * kSecond);
  EXPECT_FALSE(report().degraded) << report().status_lines.front();
  EXPECT_EQ(drops(wp::Drop::kMessageType), 0u);
  EXPECT_EQ(drops(wp::Drop::kMalformed), 0u);
  EXPECT_EQ(bridges_->monitor().tracks().size(), 0);
}

TEST_F(ForeignInput, DetectionsGoThroughTheTrackerAndAreNotRefused) {
  // One Detection3DArray: read (no refusal), its detections tentative tracks of the
  // multi-object tracker (confirmed at the second hit), so no track yet.
  const Fixture d = load("detections3d");  // stamped 17 s, frame camera
  feed(d, 17 * kSecond);
  EXPECT_FALSE(report().degraded) << report().status_lines.front();
  EXPECT_EQ(drops(wp::Drop::kMessageType), 0u);
  EXPECT_EQ(bridges_->monitor().tracks().size(), 0);
}

TEST_F(ForeignInput, MalformedBytesAreDroppedAndTheNextMessageIsRead) {
  const Fixture f = load("spencer_v1");
  feed(f, 10 * kSecond + kSecond / 10, f.bytes.size() - 3, f.type, f.md5);
  EXPECT_EQ(drops(wp::Drop::kMalformed), 1u);
  EXPECT_FALSE(statusNames("md5"));
  EXPECT_EQ(bridges_->monitor().tracks().size(), 0);
  feed(f, 10 * kSecond + 2 * kSecond / 10);
  EXPECT_EQ(bridges_->monitor().tracks().size(), 2);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
