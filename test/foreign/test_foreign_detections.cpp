// Foreign detections through the multi-object tracker (rules/foreign_detections.hpp), on
// sequences serialized by genpy from the stored upstream definitions
// (test/foreign/make_detection_fixtures.py): two people walk past each other, the detections'
// order alternates and vision_msgs' results[0].id is overloaded as a "track id" that swaps
// between them every frame. The tracks must keep their own ids, follow the true positions
// and converge to the true velocities, whatever those ids say.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "allocation_counter.hpp"   // test/shared
#include "params_expectations.hpp"  // test/shared
#include "wire_writer.hpp"          // test/foreign
#include "workspace_proximity/rules/foreign_detections.hpp"

namespace wp = workspace_proximity;

namespace {

struct Truth {
  Eigen::Vector3d position, velocity;
};

struct Frame {
  wp::Stamp stamp = 0;
  std::vector<std::uint8_t> bytes;
  std::map<std::string, Truth> truth;
};

struct Sequence {
  std::string type, md5;
  std::vector<Frame> frames;
};

Sequence readSequence(const std::string& name) {
  const std::string dir = std::string(WP_SOURCE_DIR) + "/test/foreign/fixtures/";
  Sequence s;
  std::ifstream text(dir + name + ".txt");
  std::string word;
  text >> word >> s.type >> s.md5;
  EXPECT_EQ(word, "type");
  while (text >> word) {
    if (word == "frame") {
      long long secs = 0, nsecs = 0;
      int count = 0;
      text >> secs >> nsecs >> count;
      s.frames.emplace_back();
      s.frames.back().stamp = secs * 1000000000LL + nsecs;
    } else {
      EXPECT_EQ(word, "truth");
      std::string who;
      Truth t;
      text >> who >> t.position.x() >> t.position.y() >> t.position.z() >> t.velocity.x() >>
          t.velocity.y() >> t.velocity.z();
      s.frames.back().truth[who] = t;
    }
  }
  std::ifstream in(dir + name + ".bin", std::ios::binary);
  const std::vector<std::uint8_t> all((std::istreambuf_iterator<char>(in)),
                                      std::istreambuf_iterator<char>());
  std::size_t at = 0;
  for (Frame& f : s.frames) {
    std::uint32_t length = 0;
    EXPECT_LE(at + 4, all.size());
    std::memcpy(&length, all.data() + at, 4);  // little-endian, as the machines here are
    at += 4;
    f.bytes.assign(all.begin() + static_cast<long>(at), all.begin() + static_cast<long>(at + length));
    at += length;
  }
  EXPECT_EQ(at, all.size());
  EXPECT_EQ(s.frames.size(), 30u);
  return s;
}

// `bytes` decoded into `array` as a message of the sequence's type.
wp::ForeignRefusal decode(const Sequence& s, const std::vector<std::uint8_t>& bytes,
                          wp::ForeignTrackArray* array) {
  return wp::decodeForeignTracks(s.type, s.md5, bytes.data(), bytes.size(), array);
}

wp::ForeignDetectionParams params() {
  wp::ForeignDetectionParams p;
  p.tracker.confirm_hits = 2;
  return p;
}

// Every frame through the decoder and the tracker: from the second frame on two tracks, each
// with one id for the whole walk, at its person's true place; the velocity converges.
void walk(const std::string& name, const Eigen::Isometry3d& fixed_from_camera,
          double expected_height) {
  SCOPED_TRACE(name);
  const Sequence s = readSequence(name);
  wp::ForeignDetections detections(params());
  wp::ForeignTrackArray array;
  std::map<std::string, std::string> id_of;  // person -> track id
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Frame& f = s.frames[k];
    ASSERT_EQ(decode(s, f.bytes, &array), wp::ForeignRefusal::kNone)
        << array.detail;
    EXPECT_EQ(array.stamp, f.stamp);
    ASSERT_EQ(detections.ingest(array, fixed_from_camera), wp::DetectionRefusal::kNone);
    const std::vector<wp::BoxObservation>& tracks = detections.tracks();
    if (k == 0) {
      EXPECT_TRUE(tracks.empty()) << "tentative after one detection";
      continue;
    }
    ASSERT_EQ(tracks.size(), 2u) << "frame " << k;
    for (const wp::BoxObservation& b : tracks) {
      // Its person: the nearer truth (they are at least 0.8 m apart throughout).
      std::string person;
      double best = 1e9;
      for (const auto& [who, t] : f.truth) {
        const double d = (b.position - fixed_from_camera * t.position).norm();
        if (d < best) {
          best = d;
          person = who;
        }
      }
      EXPECT_LT(best, 0.05) << "frame " << k;
      std::string& id = id_of[person];
      if (id.empty()) id = std::string(b.id);
      EXPECT_EQ(std::string(b.id), id) << "frame " << k << ": " << person << " changed id";
      EXPECT_EQ(b.label, "unknown");
      EXPECT_NEAR(b.dimensions.z(), expected_height, 1e-12);
      std::string why;
      EXPECT_EQ(wp::checkBox(b, wp::BoxLimits(), &why), wp::Drop::kCount) << why;
      if (k + 1 == s.frames.size()) {
        const Eigen::Vector3d v = fixed_from_camera.linear() * f.truth.at(person).velocity;
        EXPECT_LT((b.linear_velocity - v).norm(), 0.05) << person << " " << b.linear_velocity.transpose();
        EXPECT_TRUE(b.velocity_known);
      }
    }
  }
  ASSERT_EQ(id_of.size(), 2u);
  EXPECT_NE(id_of["A"], id_of["B"]);
}

}  // namespace

TEST(ForeignDetections, Detection3DArrayIdsAreTheTrackersNotTheMessages) {
  walk("walk_detections3d", Eigen::Isometry3d::Identity(), 1.7);
}

TEST(ForeignDetections, JskBoxesWithoutHeightTakeTheDefault) {
  walk("walk_jsk", Eigen::Isometry3d::Identity(), 1.8);
}

TEST(ForeignDetections, MarkerArraySolidMarkersAreDetections) {
  walk("walk_markers", Eigen::Isometry3d::Identity(), 1.7);
}

TEST(ForeignDetections, PoseArrayPosesTakeTheDefaultSize) {
  walk("walk_poses", Eigen::Isometry3d::Identity(), 1.8);
}

TEST(ForeignDetections, TheDebianTypesDecodeAsGenpyWroteThem) {
  // MarkerArray: per person a CYLINDER (read), a TEXT_VIEW_FACING and an ARROW (ignored), and
  // a DELETE (ignored); no header of its own: the first solid marker's stamp and frame.
  // PoseArray: its poses, without sizes. Every shorter prefix is refused.
  for (const char* name : {"walk_markers", "walk_poses"}) {
    SCOPED_TRACE(name);
    const Sequence s = readSequence(name);
    const bool markers = std::string(name) == "walk_markers";
    wp::ForeignTrackArray array;
    for (const Frame& f : s.frames) {
      ASSERT_EQ(decode(s, f.bytes, &array), wp::ForeignRefusal::kNone)
          << array.detail;
      ASSERT_EQ(array.tracks.size(), 2u);
      EXPECT_EQ(array.ignored, markers ? 5u : 0u);
      EXPECT_EQ(array.stamp, f.stamp);
      EXPECT_EQ(array.frame_id, "camera");
      EXPECT_EQ(array.version->family, wp::ForeignFamily::kDetections);
      for (const wp::ForeignTrack& t : array.tracks) {
        EXPECT_EQ(t.id_kind, wp::ForeignIdKind::kNone);
        EXPECT_EQ(t.dimension_axes, markers ? wp::kAxesAll : wp::kAxesNone);
        bool someone = false;
        for (const auto& [who, truth] : f.truth) {
          someone = someone || (t.position - truth.position).norm() < 1e-12;
        }
        EXPECT_TRUE(someone) << t.position.transpose();
      }
    }
    const std::vector<std::uint8_t>& bytes = s.frames[3].bytes;
    for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
      wp::decodeForeignTracks(s.type, s.md5, bytes.data(), cut, &array);
      EXPECT_NE(array.refusal, wp::ForeignRefusal::kNone) << "cut at " << cut;
    }
  }
}

TEST(ForeignDetections, TheTrackerRunsInTheFixedFrame) {
  // A camera 2 m up and turned 90 degrees about z: tracks, their velocities and orientations
  // come out in the fixed frame.
  Eigen::Isometry3d fixed_from_camera = Eigen::Isometry3d::Identity();
  fixed_from_camera.translate(Eigen::Vector3d(1.0, -2.0, 2.0));
  fixed_from_camera.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  walk("walk_detections3d", fixed_from_camera, 1.7);
}

TEST(ForeignDetections, TracksTypesAndOldMessagesAreRefused) {
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignDetections detections(params());
  wp::ForeignTrackArray array;
  ASSERT_EQ(decode(s, s.frames[5].bytes, &array), wp::ForeignRefusal::kNone);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()), wp::DetectionRefusal::kNone);
  ASSERT_EQ(decode(s, s.frames[4].bytes, &array), wp::ForeignRefusal::kNone);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
            wp::DetectionRefusal::kOutOfOrder);
  // A refused decode (cut short) and a people tracker's type are not detections.
  wp::decodeForeignTracks(s.type, s.md5, s.frames[6].bytes.data(), 10, &array);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
            wp::DetectionRefusal::kNotDetections);
  std::ifstream in(std::string(WP_SOURCE_DIR) + "/test/foreign/fixtures/spencer_v2.bin",
                   std::ios::binary);
  const std::vector<std::uint8_t> spencer((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
  ASSERT_EQ(wp::decodeForeignTracks("spencer_tracking_msgs/TrackedPersons",
                                    "21c0b1a57c4933e68f39aa3802861828", spencer.data(),
                                    spencer.size(), &array),
            wp::ForeignRefusal::kNone);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
            wp::DetectionRefusal::kNotDetections);
}

TEST(ForeignDetections, ACovarianceSetsTheMeasurementNoise) {
  // One detection with position variances (0.04, 0.01, 0.09) m^2: sigma = 0.3 m, the largest;
  // confirmed at once, its position error is the filter's first 3 sigma = 0.9 m. Without a
  // covariance: the default 0.05 m, 0.15 m.
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignTrackArray array;
  ASSERT_EQ(decode(s, s.frames[0].bytes, &array), wp::ForeignRefusal::kNone);
  wp::ForeignDetectionParams p = params();
  p.tracker.confirm_hits = 1;
  wp::ForeignDetections plain(p);
  plain.ingest(array, Eigen::Isometry3d::Identity());
  ASSERT_EQ(plain.tracks().size(), 2u);
  EXPECT_NEAR(plain.tracks()[0].position_error, 0.15, 1e-12);
  EXPECT_FALSE(plain.tracks()[0].velocity_known);
  array.tracks[0].has_position_covariance = true;
  array.tracks[0].position_covariance = Eigen::Vector3d(0.04, 0.01, 0.09).asDiagonal();
  wp::ForeignDetections covariant(p);
  covariant.ingest(array, Eigen::Isometry3d::Identity());
  ASSERT_EQ(covariant.tracks().size(), 2u);
  EXPECT_NEAR(covariant.tracks()[0].position_error, 0.9, 1e-12);
}

// obstacle_detector/Obstacles through the tracker, against the analytic scene. A laser frame
// 1 m along x and 2 m along y of the fixed frame, turned 90 degrees about z; in it a wall
// from (0, 1) to (2, 1) standing still and a circle (true_radius 0.25, radius 0.5) moving
// from (3, 0) along -x at 0.5 m/s, whose message says velocity (5, 5): never read. 20 Hz.
namespace {

constexpr const char* kObstaclesType = "obstacle_detector/Obstacles";
constexpr const char* kObstaclesMd5 = "043bbf49c7775f8111e850268dbcf2e3";

// `bytes` decoded into `array` as obstacle_detector/Obstacles.
wp::ForeignRefusal decodeObstacles(const std::vector<std::uint8_t>& bytes,
                                   wp::ForeignTrackArray* array) {
  return wp::decodeForeignTracks(kObstaclesType, kObstaclesMd5, bytes.data(), bytes.size(), array);
}

std::vector<std::uint8_t> obstaclesMessage(int k) {
  const double t = 0.05 * k;
  wp_test::WireWriter w;
  const long long ns = 10000000000LL + 50000000LL * k;
  w.header(static_cast<std::uint32_t>(k), static_cast<std::uint32_t>(ns / 1000000000LL),
           static_cast<std::uint32_t>(ns % 1000000000LL), "laser");
  w.u32(1);
  w.vec3(0, 1, 0);
  w.vec3(2, 1, 0);
  w.u32(1);
  w.vec3(3.0 - 0.5 * t, 0, 0);
  w.vec3(5, 5, 0);  // not read
  w.f64(0.5);
  w.f64(0.25);
  return w.bytes;
}

Eigen::Isometry3d fixedFromLaser() {
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.translate(Eigen::Vector3d(1.0, 2.0, 0.0));
  f.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  return f;
}

wp::ForeignDetectionParams obstacleParams() {
  wp::ForeignDetectionParams p = params();
  p.default_dimensions = Eigen::Vector3d(0.6, 0.6, 1.7);  // the circles' height: 1.7
  p.segment_size = Eigen::Vector3d(0.3, 0.1, 2.0);        // least length, thickness, height
  return p;
}

const wp::BoxObservation* withLabel(const std::vector<wp::BoxObservation>& tracks,
                                    std::string_view label) {
  for (const wp::BoxObservation& b : tracks) {
    if (b.label == label) return &b;
  }
  return nullptr;
}

}  // namespace

TEST(ForeignDetections, ObstacleSegmentsAndCirclesAreTrackedBoxes) {
  wp::ForeignDetections detections(obstacleParams());
  wp::ForeignTrackArray array;
  const Eigen::Isometry3d fixed_from_laser = fixedFromLaser();
  std::string wall_id, circle_id;
  for (int k = 0; k <= 40; ++k) {
    const std::vector<std::uint8_t> bytes = obstaclesMessage(k);
    ASSERT_EQ(decodeObstacles(bytes, &array), wp::ForeignRefusal::kNone)
        << array.detail;
    ASSERT_EQ(detections.ingest(array, fixed_from_laser), wp::DetectionRefusal::kNone);
    const std::vector<wp::BoxObservation>& tracks = detections.tracks();
    if (k == 0) {
      EXPECT_TRUE(tracks.empty()) << "tentative after one detection";
      continue;
    }
    ASSERT_EQ(tracks.size(), 2u) << "frame " << k;
    const wp::BoxObservation* wall = withLabel(tracks, "segment");
    const wp::BoxObservation* circle = withLabel(tracks, "unknown");
    ASSERT_NE(wall, nullptr);
    ASSERT_NE(circle, nullptr);
    if (k == 1) {
      wall_id = std::string(wall->id);
      circle_id = std::string(circle->id);
      // Two sightings 50 ms apart at 5 cm: the velocity is not known yet, whatever the
      // message's velocity field says (5, 5).
      EXPECT_FALSE(circle->velocity_known);
      EXPECT_FALSE(wall->velocity_known);
    }
    EXPECT_EQ(std::string(wall->id), wall_id);
    EXPECT_EQ(std::string(circle->id), circle_id);
    // The wall: its midpoint (1, 1) at half its height, carried into the fixed frame: (0, 3,
    // 1); 2 m long along the laser's x = the fixed frame's y, 0.1 m thick, 2 m high.
    EXPECT_LT((wall->position - Eigen::Vector3d(0.0, 3.0, 1.0)).norm(), 1e-9) << "frame " << k;
    EXPECT_NEAR(wall->dimensions.x(), 2.0, 1e-12);
    EXPECT_NEAR(wall->dimensions.y(), 0.1, 1e-12);
    EXPECT_NEAR(wall->dimensions.z(), 2.0, 1e-12);
    const Eigen::Quaterniond q(wall->quaternion.w(), wall->quaternion.x(), wall->quaternion.y(),
                               wall->quaternion.z());
    EXPECT_LT((q * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);
    // The circle: (3 - 0.5 t, 0) in the laser frame, (1, 5 - 0.5 t) in the fixed frame, on
    // the floor at half the height 1.7; 0.5 m across (the true radius), 1.7 m high.
    const double t = 0.05 * k;
    const Eigen::Vector3d truth(1.0, 5.0 - 0.5 * t, 0.85);
    EXPECT_NEAR(circle->dimensions.x(), 0.5, 1e-12);
    EXPECT_NEAR(circle->dimensions.y(), 0.5, 1e-12);
    EXPECT_NEAR(circle->dimensions.z(), 1.7, 1e-12);
    EXPECT_NEAR(circle->position.z(), 0.85, 1e-9);
    if (k >= 20) {
      // Noise-free constant-velocity data: the filter converges to the motion itself.
      EXPECT_LT((circle->position - truth).norm(), 2e-3) << "frame " << k;
      EXPECT_LT((circle->linear_velocity - Eigen::Vector3d(0.0, -0.5, 0.0)).norm(), 2e-2)
          << "frame " << k << ": " << circle->linear_velocity.transpose();
      EXPECT_TRUE(circle->velocity_known);
      EXPECT_LT(wall->linear_velocity.norm(), 1e-9);
      EXPECT_TRUE(wall->velocity_known);
    }
    std::string why;
    EXPECT_EQ(wp::checkBox(*wall, wp::BoxLimits(), &why), wp::Drop::kCount) << why;
    EXPECT_EQ(wp::checkBox(*circle, wp::BoxLimits(), &why), wp::Drop::kCount) << why;
  }
}

TEST(ForeignDetections, AShortSegmentTakesTheLeastLengthAndSegmentsKeepToTheirLabel) {
  // A 5 cm segment becomes a 0.3 m box (the least length). A circle and a segment at the same
  // place are never associated with each other: each keeps a track of its own label.
  wp_test::WireWriter w;
  w.header(0, 10, 0, "laser");
  w.u32(1);
  w.vec3(0, 0, 0);
  w.vec3(0, 0.05, 0);
  w.u32(1);
  w.vec3(0, 0.025, 0);
  w.vec3(0, 0, 0);
  w.f64(0.3);
  w.f64(0.2);
  wp::ForeignTrackArray array;
  ASSERT_EQ(decodeObstacles(w.bytes, &array), wp::ForeignRefusal::kNone);
  wp::ForeignDetectionParams p = obstacleParams();
  p.tracker.confirm_hits = 1;
  wp::ForeignDetections detections(p);
  ASSERT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()), wp::DetectionRefusal::kNone);
  ASSERT_EQ(detections.tracks().size(), 2u);
  const wp::BoxObservation* segment = withLabel(detections.tracks(), "segment");
  ASSERT_NE(segment, nullptr);
  EXPECT_NEAR(segment->dimensions.x(), 0.3, 1e-12);
  EXPECT_NEAR(segment->dimensions.y(), 0.1, 1e-12);
  EXPECT_NEAR(segment->position.z(), 1.0, 1e-12);
  const wp::BoxObservation* circle = withLabel(detections.tracks(), "unknown");
  ASSERT_NE(circle, nullptr);
  EXPECT_NEAR(circle->dimensions.x(), 0.4, 1e-12);
  EXPECT_NE(segment->id, circle->id);
}

TEST(ForeignDetections, DetectionsInAnotherFrameAreSkippedAndCounted) {
  // Detection3D and jsk boxes have headers of their own: one naming another frame than the
  // message's is skipped (one message, one transform), never placed with the message's pose.
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignTrackArray array;
  ASSERT_EQ(decode(s, s.frames[0].bytes, &array), wp::ForeignRefusal::kNone);
  ASSERT_EQ(array.tracks.size(), 2u);
  wp::ForeignDetectionParams p = params();
  p.tracker.confirm_hits = 1;
  wp::ForeignDetections same(p);
  ASSERT_EQ(same.ingest(array, Eigen::Isometry3d::Identity()), wp::DetectionRefusal::kNone);
  EXPECT_EQ(same.tracks().size(), 2u);
  EXPECT_EQ(same.skippedFrame(), 0u);
  array.tracks[1].frame_id = "elsewhere";
  wp::ForeignDetections other(p);
  ASSERT_EQ(other.ingest(array, Eigen::Isometry3d::Identity()), wp::DetectionRefusal::kNone);
  EXPECT_EQ(other.skippedFrame(), 1u);
  ASSERT_EQ(other.tracks().size(), 1u);
  EXPECT_LT((other.tracks()[0].position - array.tracks[0].position).norm(), 1e-12);
  // An empty array frame: the first element's is the message's (as the input bridge places it).
  array.frame_id = {};
  wp::ForeignDetections first(p);
  ASSERT_EQ(first.ingest(array, Eigen::Isometry3d::Identity()), wp::DetectionRefusal::kNone);
  EXPECT_EQ(first.skippedFrame(), 1u);
  EXPECT_EQ(first.tracks().size(), 1u);
}

// ~detection_tracker/ (the node's parameters) reach the tracker of every detection input:
// each value as set, the defaults TrackerParams' own, and a changed value changes what the
// tracker does (confirm_hits 1: obstacle_detector's wall and circle are tracks at once;
// max_misses 1: one message without them deletes both).
TEST(ForeignDetections, TheNodesDetectionTrackerParametersReachTheTracker) {
  const wp::TrackerParams code;
  const wp::TrackerParams defaults = wp::foreignDetectionParams(wp::MonitorParams()).tracker;
  wp_test::expectSameTrackerSettings(defaults, code);

  wp::MonitorParams p;
  p.detection_tracker.gate_chi2 = 9.5;
  p.detection_tracker.gate_distance = 0.75;
  p.detection_tracker.confirm_hits = 1;
  p.detection_tracker.max_misses = 1;
  p.detection_tracker.timeout = 0.4;
  p.detection_tracker.known_velocity_error = 0.3;
  ASSERT_TRUE(wp::validate(p).empty());
  const wp::ForeignDetectionParams fp = wp::foreignDetectionParams(p);
  wp_test::expectSameTrackerSettings(fp.tracker, p.detection_tracker);  // the values just set

  wp::ForeignDetections detections(fp);
  wp::ForeignTrackArray array;
  std::vector<std::uint8_t> bytes = obstaclesMessage(0);
  ASSERT_EQ(decodeObstacles(bytes, &array), wp::ForeignRefusal::kNone)
      << array.detail;
  ASSERT_EQ(detections.ingest(array, fixedFromLaser()), wp::DetectionRefusal::kNone);
  EXPECT_EQ(detections.tracks().size(), 2u) << "confirm_hits 1: confirmed at once";
  // The next message with neither obstacle (no segments, no circles), 50 ms later.
  wp_test::WireWriter w;
  w.header(1, 10, 50000000, "laser");
  w.u32(0);
  w.u32(0);
  ASSERT_EQ(decodeObstacles(w.bytes, &array), wp::ForeignRefusal::kNone)
      << array.detail;
  ASSERT_EQ(detections.ingest(array, fixedFromLaser()), wp::DetectionRefusal::kNone);
  EXPECT_TRUE(detections.tracks().empty()) << "max_misses 1: deleted after one miss";
}

TEST(ForeignDetections, NoAllocationOnceWarm) {
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignDetections detections(params());
  wp::ForeignTrackArray array;
  long before = 0;
  for (int round = 0; round < 3; ++round) {
    if (round == 1) before = wp_test::allocationCount();
    for (const Frame& f : s.frames) {
      decode(s, f.bytes, &array);
      array.stamp += round * 3000000000LL;  // later rounds later in time
      ASSERT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
                wp::DetectionRefusal::kNone);
    }
  }
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
